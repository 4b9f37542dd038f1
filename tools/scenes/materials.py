"""Looks several scenes share: the mirror extension's defaults and the light colours."""

from speculum_py.enums import MODE


def mirror_ext(**over):
    e = {"mode": MODE.screen_space, "maxScreenSpaceRoughness": 0.6}
    e.update(over)
    return e


SUN_COLOR = (1.0, 0.93, 0.82)
LAMP_COLOR = (1.0, 0.86, 0.7)
