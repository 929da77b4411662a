#!/bin/bash
# The link-time optimisation guard (src/core/CMakeLists.txt): configure a
# scratch build with CMAKE_INTERPROCEDURAL_OPTIMIZATION=ON and check that
# CMake warns, that the core libraries compile without -flto and that the
# Python bindings do get it (so the check can tell the two apart).
# Usage: check_ipo_guard.sh SOURCE_DIR CMAKE PYTHON3 SCRATCH_DIR
set -u
src=$1 cmake=$2 py=$3 dir=$4
rm -rf "$dir"
log=$("$cmake" -S "$src" -B "$dir" -G "Unix Makefiles" -DCMAKE_BUILD_TYPE=Release \
      -DPython3_EXECUTABLE="$py" -DCMAKE_INTERPROCEDURAL_OPTIMIZATION=ON -DMARBLE_BUILD_TESTS=OFF 2>&1)
rc=$?
fail() { echo "FAIL: $*"; rm -rf "$dir"; exit 1; }
[ $rc -eq 0 ] || { echo "$log" | tail -20; fail "configure failed (rc $rc)"; }
echo "$log" | tr '\n' ' ' | grep -q "CMAKE_INTERPROCEDURAL_OPTIMIZATION=ON: Marble's core" \
  || fail "no warning about link-time optimisation"
for t in marble_core marble_colloid; do
  f="$dir/src/core/CMakeFiles/$t.dir/flags.make"
  [ -f "$f" ] || fail "$f missing"
  ! grep -q -- "-flto" "$f" || fail "$t is compiled with -flto: $(grep -- -flto "$f")"
done
f="$dir/src/script_interface/CMakeFiles/_marble.dir/flags.make"
[ -f "$f" ] || fail "$f missing"
grep -q -- "-flto" "$f" || fail "the bindings lack -flto: the check cannot see the option"
echo "ok: warned; marble_core and marble_colloid without -flto, _marble with it"
rm -rf "$dir"
