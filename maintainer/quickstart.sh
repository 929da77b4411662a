#!/usr/bin/env bash
# Quick start on Debian 12: install the missing dependencies (apt), configure
# and build Marble in build/ (Release, default features), then run the main job.
#
#   bash maintainer/quickstart.sh
#
# Environment: MARBLE_MAIN_JOB overrides the job below, MARBLE_JOBS the number
# of parallel compile jobs (default: all cores).
set -euo pipefail

# The main job: what a new user runs first (relative to the repository root).
MAIN_JOB="${MARBLE_MAIN_JOB:-build/pymarble samples/marble_colloid.py}"

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"
# shellcheck source=maintainer/install_deps.sh
source maintainer/install_deps.sh

t0=$SECONDS
marble_install_deps
t1=$SECONDS

cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 \
  -DMARBLE_MYCONFIG="$ROOT/maintainer/configs/default.hpp"
make -C build -j"${MARBLE_JOBS:-$(nproc)}"
t2=$SECONDS

echo "[quickstart] running: ${MAIN_JOB}"
eval "${MAIN_JOB}"
t3=$SECONDS

echo "[quickstart] done: dependencies $((t1 - t0)) s, configure+build $((t2 - t1)) s, main job $((t3 - t2)) s"
echo "[quickstart] next: bash maintainer/run_tests.sh   (the test suite)"
