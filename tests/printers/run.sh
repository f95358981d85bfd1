#!/usr/bin/env bash
# Independent checks of the printed formulas (issue 20): the snapshots of the printers were
# recorded from the printers themselves; these checks hold them against other tools.
#
#   bash tests/printers/run.sh            # from anywhere; .ci/run calls it before the e2e test
#
# 1. Installs what it needs when missing (idempotent, a no-op when present): Node.js + npm
#    (apt, as tests/e2e/run.sh), the pinned katex from tests/printers/package-lock.json into
#    tests/printers/node_modules (git-ignored, `npm ci`), and, unless python3 already has the
#    pinned SymPy and mpmath, a venv tests/printers/.venv (git-ignored) with
#    tests/printers/requirements.txt.
# 2. Writes every formula of a representative set (cube, cylinder, frustum, a composite of
#    interpolated patches, a piecewise function and curve, random expressions, every function)
#    with Graph::eval's values at 200 points: the printer_cases example of crates/geomkit.
# 3. check.mjs: the JavaScript printer's output (inline, definitions, program) run by node
#    against Graph::eval (1e-13 relative); every LaTeX and Desmos text rendered by KaTeX with
#    throwOnError and evaluated from KaTeX's parse tree against Graph::eval (1e-13; braces
#    group nothing, as on the page). mathematica.py: every Mathematica text parsed by SymPy's
#    parse_mathematica and evaluated (mpmath, 30 digits) against Graph::eval (1e-13).
#    Maple: no free parser exists; its printer is covered by the snapshots only.
#
# Environment: PRINTERS_OUT (default target/printers).
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$PWD
here=$root/tests/printers
out=${PRINTERS_OUT:-$root/target/printers}

tag=printers
# shellcheck source=../lib.sh
source "$root/tests/lib.sh"

# --- 1. tools -----------------------------------------------------------------------------
need_node
pinned=$(node -p "require('$here/package-lock.json').packages['node_modules/katex'].version")
have=$(node -p "try { require('$here/node_modules/katex/package.json').version } catch { '' }")
if [ "$have" != "$pinned" ]; then
    say "npm ci (katex $pinned)"
    (cd "$here" && npm ci --no-audit --no-fund --loglevel=error >/dev/null) ||
        die "npm ci in tests/printers failed"
fi

python=${PYTHON:-python3}
wanted=$(grep -E '^[a-z]+==' "$here/requirements.txt" | sort | tr '\n' ' ')
found=$("$python" -c 'import sympy, mpmath; print(" ".join(sorted(["mpmath==" + mpmath.__version__, "sympy==" + sympy.__version__])) + " ")' 2>/dev/null || true)
if [ "$found" != "$wanted" ]; then
    venv=$here/.venv
    venv_with "$venv" "$here/requirements.txt" "$venv/.requirements.installed"
    python=$venv/bin/python
fi
say "node $(node --version), katex $pinned, $("$python" -c 'import sympy; print("sympy", sympy.__version__)')"

# --- 2. the formulas ----------------------------------------------------------------------
mkdir -p "$out"
cargo run --release --quiet -p geomkit --example printer_cases -- "$out/cases.json" ||
    die "the printer_cases example failed"

# --- 3. the checks ------------------------------------------------------------------------
status=0
node "$here/check.mjs" "$out/cases.json" || status=1
"$python" "$here/mathematica.py" "$out/cases.json" || status=1
[ "$status" -eq 0 ] || die "a printer's output disagrees with an independent tool (above)"
say "ok"
