#!/usr/bin/env bash
# Installs what is missing, builds Release into build/, runs the default suite and prints the path
# of its HTML report (CONTRACT §1). Extra arguments go to `aoeval run` (e.g. --suite quick); the
# default suite is asked for only when they name none (--suite may be given once).
set -euo pipefail
cd "$(dirname "$0")"
tools/bootstrap.sh
for arg in "$@"; do
  case "$arg" in
    --suite | --suite=*) exec build/aoeval run "$@" ;;
  esac
done
exec build/aoeval run --suite default "$@"
