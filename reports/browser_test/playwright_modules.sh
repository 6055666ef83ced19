#!/usr/bin/env bash
# Sourced by the browser tests: playwright_modules HERE BUILD CHROMIUM prints the node_modules
# folder that holds playwright-core (installed with `npm ci` from HERE/package-lock.json into
# BUILD/browser_test, again only when the lock changes), or returns 77 (ctest: skipped) when
# chromium or node is absent (./test.sh installs both) or npm cannot install playwright-core.
playwright_modules() {
  local here="$1" build="$2" chromium="$3"
  if [ ! -x "$chromium" ]; then
    echo >&2 "browser_test: skipped: $chromium is not installed (./test.sh installs Debian's chromium)"
    return 77
  fi
  if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
    echo >&2 "browser_test: skipped: node and npm are not installed (./test.sh installs them)"
    return 77
  fi

  local modules="$build/browser_test"
  if ! cmp -s "$here/package-lock.json" "$modules/package-lock.json" ||
     [ ! -f "$modules/node_modules/playwright-core/package.json" ]; then
    rm -rf "$modules"
    mkdir -p "$modules"
    cp "$here/package.json" "$here/package-lock.json" "$modules/"
    # The npm registry is this test's one source outside Debian: retry its fetches, and skip (77)
    # rather than fail when it cannot be reached, since that says nothing about aoeval's pages.
    if ! (cd "$modules" && npm ci --ignore-scripts --no-audit --no-fund --loglevel=error \
            --fetch-retries=5 --fetch-retry-mintimeout=2000 --fetch-retry-maxtimeout=30000 >&2); then
      rm -rf "$modules"
      echo >&2 "browser_test: skipped: npm ci could not install playwright-core (is the npm registry reachable?)"
      return 77
    fi
  fi
  echo "$modules"
}
