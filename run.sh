#!/usr/bin/env bash
# Installs what is missing, builds Release into build/, runs the default suite and prints the path
# of its HTML report (CONTRACT §1). Extra arguments go to `aoeval run` (e.g. --suite quick).
set -euo pipefail
cd "$(dirname "$0")"
tools/bootstrap.sh
exec build/aoeval run --suite default "$@"
