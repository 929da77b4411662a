"""``espressomd.code_info``: the compiled and known features, with ESPResSo's
names (the same lists as :func:`espressomd.features` / :func:`espressomd.all_features`)."""
from .code_features import features, all_features  # noqa: F401
