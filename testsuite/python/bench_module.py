"""Import a script of bench/ as a module, for the tests that check a bench's helpers
(a helper module: ctest registers test_*.py only)."""
import importlib.util
import os

BENCH_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bench")


def load_bench(name):
    """bench/<name>.py as a module (its main() is not run)."""
    spec = importlib.util.spec_from_file_location(name, os.path.join(BENCH_DIR, name + ".py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
