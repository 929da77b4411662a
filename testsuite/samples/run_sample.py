"""Run one sample as a test (testsuite/samples/CMakeLists.txt): the sample
script as __main__ with no arguments. A FeaturesError naming features this
build lacks is a skip (exit code 5), so a reduced build (maintainer/configs/
minimal.hpp) reports the samples it cannot run as skipped, not failed; any
other error, or a FeaturesError for a feature the build has, still fails."""
import re
import runpy
import sys

import marble


def main(path):
    sys.argv = [path]
    try:
        runpy.run_path(path, run_name="__main__")
    except marble.FeaturesError as e:
        named = re.findall(r"[A-Z][A-Z0-9_]{2,}", str(e))
        if named and all(not marble.has_features(n) for n in named):
            print(f"SKIP {path}: {e}")
            sys.exit(5)
        raise


if __name__ == "__main__":
    main(sys.argv[1])
