"""Independent check of geomkit's Mathematica printer (tests/printers/run.sh runs this).

    python3 tests/printers/mathematica.py CASES.json

Every Mathematica expression of CASES.json (from the printer_cases example) is parsed by
SymPy's `parse_mathematica` and evaluated with 30 significant digits (mpmath) at the case's
points;
every value must be within 1e-13 relative (to max(1, |value|)) of `Graph::eval`'s. A
misprinted precedence, a wrong function name or bracket fails to parse or gives another value.
(Maple has no free parser to check its printer against; its output is covered by the
snapshots only.)
"""

import json
import math
import re
import sys

import mpmath
import sympy
from sympy.parsing.mathematica import parse_mathematica


def expected(v):
    if isinstance(v, str):
        return {"NaN": math.nan, "inf": math.inf, "-inf": -math.inf}[v]
    return v


def main():
    mpmath.mp.dps = 30
    cases = json.load(open(sys.argv[1]))["cases"]
    failures, values = [], 0
    for case in cases:
        symbols = [sympy.Symbol(v) for v in case["vars"]]
        for out in case["outputs"]:
            what = f"{case['name']}.{out['name']}"
            # Mathematica's scientific notation 1.5*^-17 (= 1.5 10^-17), which
            # parse_mathematica does not know: as a power of ten, right after a number only.
            text = re.sub(r"(\d)\*\^(-?\d+)", r"\1*10^(\2)", out["mathematica"])
            try:
                expr = parse_mathematica(text)
            except Exception as e:  # noqa: BLE001 - any parse failure is a finding
                failures.append(f"{what}: parse_mathematica failed: {e}\n    {out['mathematica'][:300]}")
                continue
            free = {str(s) for s in expr.free_symbols} - set(case["vars"])
            if free:
                failures.append(f"{what}: unknown names {sorted(free)}")
                continue
            f = sympy.lambdify(symbols, expr, modules="mpmath")
            for point, want in zip(case["points"], out["values"]):
                values += 1
                want = expected(want)
                try:
                    value = f(*[mpmath.mpf(x) for x in point])
                    got = complex(value)
                except (ValueError, ZeroDivisionError, TypeError):
                    value, got = "no number", complex(math.nan)
                if math.isnan(want) or math.isnan(got.real):
                    if not (math.isnan(want) and math.isnan(got.real)):
                        failures.append(f"{what} at {point}: {value}, eval gives {want}")
                    continue
                if got.imag != 0 or abs(got.real - want) > 1e-13 * max(1.0, abs(want)):
                    failures.append(f"{what} at {point}: {value}, eval gives {want}")
    summary = f"{len(cases)} formulas: {values} Mathematica values (SymPy {sympy.__version__} parse_mathematica) against Graph::eval"
    if failures:
        print(f"printers: {len(failures)} failures ({summary})", file=sys.stderr)
        for f in failures[:15]:
            print(f"  {f}", file=sys.stderr)
        sys.exit(1)
    print(f"printers: ok, {summary}")


if __name__ == "__main__":
    main()
