"""The names Speculum's glTF extensions use (engine/scene/EXTENSIONS.md), in one table: the
generator, the scene checks and speculum-probes write and test these strings, and a misspelt
member (KIND.cmoo) fails at once instead of writing a scene the engine rejects."""

from types import SimpleNamespace

REFLECT_EXT = "SPECULUM_reflections"
PROBE_EXT = "SPECULUM_reflection_probe"


def _enum(*names):
    # .names keeps the declared order: argparse choices and help text read from it
    return SimpleNamespace(names=names, **{n: n for n in names})


MODE = _enum("off", "screen_space", "probes_only", "local_cubemap_only")  # SPECULUM_reflections.mode
KIND = _enum("local_cubemap", "cmo", "planar")  # SPECULUM_reflection_probe.kind
SHAPE = _enum("box", "sphere")  # SPECULUM_reflection_probe.shape
UPDATE = _enum("once", "on_demand", "every_frame", "time_sliced")  # SPECULUM_reflection_probe.update
