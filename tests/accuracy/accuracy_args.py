"""The command line every accuracy test starts from: this build's tools, which CMake passes to
each test alike, and the thresholds file the tests share."""
import argparse
from pathlib import Path

HERE = Path(__file__).resolve().parent


def tool_parser():
    p = argparse.ArgumentParser()
    for tool in ("capture", "reference", "metrics"):
        p.add_argument(f"--{tool}", required=True)
    p.add_argument("--thresholds", default=str(HERE / "thresholds.json"))
    return p
