#!/usr/bin/env bash
# The sanitizer test tier (issue 33, item 1): builds walker's compiled core with
# AddressSanitizer and UndefinedBehaviorSanitizer (setup.py with WALKER_SANITIZE=1) into a
# temporary copy of the package, and runs the C-facing tests against it.
#
#   scripts/sanitize_tests.sh [pytest arguments]   (default: the tier's test files)
#
# The interpreter itself is not instrumented, so libasan is preloaded; leak detection is
# off (CPython keeps memory until exit by design); the first UBSan report stops the run.
# Any sanitizer report ends the process with a non-zero status, so the tier fails.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d "${TMPDIR:-/tmp}/walker-sanitize.XXXXXX")
trap 'rm -rf "$work"' EXIT

cd "$repo"
# the package's Python files, without any compiled extension or bytecode of the worktree
tar --exclude='*.so' --exclude='__pycache__' -cf - walker | tar -C "$work" -xf -
# the scenes, for the tests that name them relative to the working directory
ln -s "$repo/gaits" "$work/gaits"
WALKER_SANITIZE=1 python setup.py -q build_ext --build-lib "$work" --build-temp "$work/build" \
  >"$work/build.log" 2>&1 || { cat "$work/build.log"; exit 1; }

cc=$(python -c "import sysconfig; print((sysconfig.get_config_var('CC') or 'gcc').split()[0])")
asan=$("$cc" -print-file-name=libasan.so)
if [ ! -e "$asan" ]; then
  echo "sanitize_tests: libasan.so not found by $cc; install the compiler's sanitizer runtime" >&2
  exit 1
fi

if [ "$#" -eq 0 ]; then
  set -- "$repo/tests/test_binding_safety.py" "$repo/tests/test_sanitize.py" \
    "$repo/tests/test_integrate.py" "$repo/tests/test_extension_point.py" \
    "$repo/tests/test_compiled_search.py" "$repo/tests/test_search_callbacks.py" \
    "$repo/tests/test_basin.py" \
    "$repo/tests/test_hardening.py" "$repo/tests/test_guard_screening.py"
fi
# cwd = the copy, so `import walker` finds the sanitized build first
cd "$work"
# libstdc++ too: C++ extensions the tests load (matplotlib's) throw exceptions, which the
# ASan runtime intercepts only when it finds the real __cxa_throw at start-up
export LD_PRELOAD="$asan $("$cc" -print-file-name=libstdc++.so)"
export ASAN_OPTIONS="detect_leaks=0:abort_on_error=1"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1"
export WALKER_SANITIZER_TIER=1
# the allocator of every Python object is malloc, so a write past one is seen too
export PYTHONMALLOC=malloc
export PYTHONPATH="$work${PYTHONPATH:+:$PYTHONPATH}"
python -c "import walker, walker._hybrid as h; assert h.__file__.startswith('$work'), h.__file__"
# --capture=sys: a sanitizer's report (written to fd 2) reaches the terminal, not a capture
# file lost when the report ends the process
python -m pytest -q -n 0 -p no:cacheprovider --capture=sys -m "not slow" --rootdir "$repo" "$@"
