"""The ending the capture tests that collect their failures share: one line on stderr naming
them, and the exit status CTest reads."""
import sys


def verdict(failures, what, sep=", "):
    if failures:
        print(what + sep.join(failures), file=sys.stderr)
        return 1
    return 0
