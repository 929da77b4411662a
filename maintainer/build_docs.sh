#!/usr/bin/env bash
# Build the HTML manual (doc/ -> build/doc-html) with warnings as errors.
# Needs a built package in build/ (autodoc imports marble) and the Debian
# packages python3-sphinx, python3-myst-parser, python3-nbsphinx and pandoc
# (nbsphinx converts the tutorials' Markdown cells with it; notebooks are never
# executed here). Exits 77 (ctest: skipped) when one of them is missing.
#
#   bash maintainer/build_docs.sh [BUILD_DIR] [OUT_DIR]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-$root/build}
out=${2:-$build/doc-html}
if [[ ! -d $build/src/python/marble ]]; then
  echo "build_docs.sh: no built marble package in $build/src/python (build first)" >&2
  exit 2
fi
if ! /usr/bin/python3 -c "import sphinx, myst_parser, nbsphinx" 2>/dev/null || ! command -v pandoc >/dev/null; then
  echo "build_docs.sh: needs python3-sphinx, python3-myst-parser, python3-nbsphinx and pandoc" \
       "(bash maintainer/install_deps.sh)" >&2
  exit 77
fi
export PYTHONPATH="$build/src/python${PYTHONPATH:+:$PYTHONPATH}"
# a full build every time: an incremental one reports warnings only for changed pages
rm -rf "$build/doc-doctrees"
exec /usr/bin/python3 -m sphinx -W --keep-going -q -b html -d "$build/doc-doctrees" \
  "$root/doc" "$out"
