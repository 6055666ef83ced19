#!/usr/bin/env bash
# The same bootstrap as run.sh, then the whole test suite through ctest (CONTRACT §1).
set -euo pipefail
cd "$(dirname "$0")"
tools/bootstrap.sh --test
ctest --test-dir build --output-on-failure --parallel "$(nproc)" "$@"
