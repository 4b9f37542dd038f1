"""speculum-probes place, as a package: scene.py reads the scene (geometry, materials, cameras),
candidates.py proposes CMO centres from geometry alone, edit.py writes the edited glTF,
measure.py renders and scores a configuration, loop.py is the greedy ADD/MOVE/DROP/ORDER/RESOLUTION
search and report.py its report. speculum_probes.py beside it is the command line."""

import sys
from pathlib import Path

# The shared glTF reader and ray caster live in the source tree's tools/speculum_py, and the
# bench this tool scores with in tests/bench: both found from this file's place
# (modules/probes/tools/placement/__init__.py, four levels below the source root), so the
# tool runs from the source tree through the build folder's wrapper without installing anything.
SOURCE = Path(__file__).resolve().parents[4]
for _folder in (SOURCE / "tests" / "bench", SOURCE / "tools"):
    if str(_folder) not in sys.path:
        sys.path.insert(0, str(_folder))
