#!/usr/bin/env bash
# The README's test command: installs dependencies, builds, runs the whole test suite; a skipped test
# that tests/skip_allowlist.txt does not allow fails it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh
# A skipped test fails the run unless tests/skip_allowlist.txt allows it (scripts/check_skips.py).
rm -f build/ctest_junit.xml
status=0
ctest --test-dir build --output-on-failure -j"$(nproc)" --output-junit ctest_junit.xml || status=$?
python3 scripts/check_skips.py build/ctest_junit.xml tests/skip_allowlist.txt || status=1
exit $status
