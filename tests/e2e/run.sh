#!/usr/bin/env bash
# End-to-end test of the demo gallery in a real browser (issue 6).
#
#   bash tests/e2e/run.sh            # from anywhere; .ci/run calls it last
#
# 1. Installs what it needs when missing (idempotent, a no-op when present): Debian's
#    chromium (/usr/bin/chromium), Node.js + npm, and the pinned playwright-core from
#    tests/e2e/package-lock.json into tests/e2e/node_modules (git-ignored). playwright-core
#    never downloads a browser: check.mjs drives Debian's chromium.
# 2. Runs `geomkit demo --out target/e2e/demo` (release build).
# 3. check.mjs serves that folder on 127.0.0.1 (a free port), opens index.html in headless
#    chromium, asserts every image loaded, every link / object / embed / iframe target
#    resolves, no console errors, every item has a caption and no failing check, and saves
#    screenshots to target/e2e/ (index.png, index-top.png, index-narrow.png, items/ID.png).
# 4. editor.mjs starts `geomkit serve` and drives the editor with the mouse (issue 25):
#    editor-*.png screenshots and the redraw rate of a 2000-point drag.
#
# Environment: CHROMIUM (default /usr/bin/chromium), E2E_OUT (default target/e2e),
# E2E_SKIP_DEMO=1 to check an existing E2E_OUT/demo without running the demo.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
here=$root/tests/e2e
out=${E2E_OUT:-$root/target/e2e}
chromium=${CHROMIUM:-/usr/bin/chromium}

tag=e2e
# shellcheck source=../lib.sh
source "$root/tests/lib.sh"

# --- 1. tools -----------------------------------------------------------------------------
if [ ! -x "$chromium" ]; then
    [ "$chromium" = /usr/bin/chromium ] || die "CHROMIUM=$chromium is not executable"
    apt_install chromium
    [ -x "$chromium" ] || die "chromium was installed but $chromium is missing"
fi
need_node
node_major=$(node -p 'process.versions.node.split(".")[0]')
if [ "$node_major" -lt 20 ]; then
    die "Node.js $(node --version) is too old for playwright-core (its package.json asks for 20 or newer)"
fi

pinned=$(node -p "require('$here/package-lock.json').packages['node_modules/playwright-core'].version")
have=$(node -p "try { require('$here/node_modules/playwright-core/package.json').version } catch { '' }")
if [ "$have" != "$pinned" ]; then
    say "npm ci (playwright-core $pinned; no browser download)"
    (cd "$here" && PLAYWRIGHT_SKIP_BROWSER_DOWNLOAD=1 npm ci --no-audit --no-fund \
        --loglevel=error >/dev/null) || die "npm ci in tests/e2e failed"
fi
say "$("$chromium" --version 2>/dev/null | head -n1), node $(node --version), playwright-core $pinned"

# --- 2. the demo --------------------------------------------------------------------------
demo_dir=$out/demo
demo_status=0
if [ "${E2E_SKIP_DEMO:-}" != 1 ]; then
    rm -rf "$demo_dir"
    mkdir -p "$out"
    say "cargo run --release -p geomkit-cli -- demo --out $demo_dir"
    cargo run --release --quiet -p geomkit-cli -- demo --out "$demo_dir" >"$out/demo.log" 2>&1 ||
        demo_status=$?
    tail -n 3 "$out/demo.log" >&2
fi
[ -f "$demo_dir/index.html" ] || die "the demo wrote no $demo_dir/index.html (see $out/demo.log)"

# --- 3. the browser -----------------------------------------------------------------------
check_status=0
timeout --kill-after=10 300 node "$here/check.mjs" --dir "$demo_dir" --out "$out" \
    --chromium "$chromium" || check_status=$?
if [ "$check_status" -eq 124 ] || [ "$check_status" -eq 137 ]; then
    die "check.mjs timed out after 300 s"
fi
[ "$demo_status" -eq 0 ] || die "geomkit demo exited with $demo_status (see $out/demo.log)"
[ "$check_status" -eq 0 ] || die "the gallery check failed (messages above; screenshots in $out)"

# --- 4. the editor (issue 25) ---------------------------------------------------------------
# `geomkit serve` on a free port, the page driven with the mouse (editor.mjs): drawn shapes
# against the API and references, undo/redo, files, and the redraw rate of a 2000-point drag.
cargo build --release --quiet -p geomkit-cli
editor_status=0
timeout --kill-after=10 300 node "$here/editor.mjs" --geomkit "$root/target/release/geomkit" \
    --out "$out" --chromium "$chromium" || editor_status=$?
[ "$editor_status" -eq 0 ] || die "the editor check failed (messages above; screenshots in $out)"
timeout --kill-after=10 300 node "$here/editor-tables.mjs" --geomkit "$root/target/release/geomkit" --out "$out" --chromium "$chromium" || die "the editor's tables and weights check failed (messages above; screenshots in $out)"
timeout --kill-after=10 300 node "$here/editor-3d.mjs" --geomkit "$root/target/release/geomkit" --out "$out" --chromium "$chromium" || die "the editor's 3-D check failed (messages above; screenshots in $out)"
timeout --kill-after=10 300 node "$here/editor-body.mjs" --geomkit "$root/target/release/geomkit" --out "$out" --chromium "$chromium" || die "the editor's body tab and file round trips check failed (messages above; screenshots in $out)"
say "ok: screenshots in $out"
