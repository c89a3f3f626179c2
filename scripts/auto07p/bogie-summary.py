#!/usr/bin/env python3
"""The small text summary of one AUTO-07p run of bogie.f90 that tests/auto07p_bogie.rs reads
(written by scripts/auto07p-bogie to tests/data/auto07p/bogie/ntst-<N>.txt):

    python3 bogie-summary.py s.hb s.po d.po UZR-SPEEDS... > ntst-<N>.txt

Plain Python (no numpy). Lines, SI units unless the name says otherwise:
    hopf <V_H m/s> <frequency Hz>                  the HB point of s.hb (frequency 1/PAR(11))
    fold <V m/s> <max y1 mm> <period s>            each LP of s.po, in branch order
    cycle <V> <period> <max y1 mm> <largest nontrivial |multiplier|> <PT> <x0: 12 values, SI>
                                                   each UZ point at one of UZR-SPEEDS (AUTO
                                                   locates them to about 1e-9 relative; the
                                                   UZSTOP end point is not one of them)
max y1 is the largest |U(1)| (leading wheelset, mm) of AUTO's collocation polynomials (degree
NCOL on each mesh interval, through its NCOL + 1 stored points), maximised by golden section;
x0 is the state at AUTO's t = 0 (U(1..6) mm/mrad -> m/rad, U(7..12) times OMS/1000). The
largest nontrivial multiplier drops the one nearest 1 (AUTO prints 6 significant digits).
"""
import math
import re
import sys

OMS = 60.0  # bogie.f90's rate scale (rad/s)


def number(s):
    s = s.replace("D", "E")
    try:
        return float(s)
    except ValueError:  # AUTO's three-digit exponents without the E: 1.2-308
        k = max(s.rfind("+"), s.rfind("-"))
        return float(s[:k] + "E" + s[k:])


def solutions(path):
    lines = open(path).read().splitlines()
    i, out = 0, []
    while i < len(lines):
        h = [int(v) for v in lines[i].split()]
        pt, ty, nfpr, ntpl, nar, nrowpr, ncol, npar = h[1], h[2], h[4], h[6], h[7], h[8], h[10], h[11]
        body = [number(v) for l in lines[i + 1:i + 1 + nrowpr] for v in l.split()]
        rows = [body[k * nar:(k + 1) * nar] for k in range(ntpl)]
        k = ntpl * nar + 2 * nfpr + ntpl * (nar - 1)
        par = [math.nan] + body[k:k + npar]
        out.append(dict(pt=pt, ty=ty, t=[r[0] for r in rows], u=[r[1:] for r in rows],
                        ncol=ncol, par=par))
        i += 1 + nrowpr
    return out


def collocation_max(s):
    m, t, y = s["ncol"], s["t"], [u[0] for u in s["u"]]
    best = max(abs(v) for v in y)
    g = 0.5 * (math.sqrt(5.0) - 1.0)
    for j in range((len(t) - 1) // m):
        ts, ys = t[j * m:j * m + m + 1], y[j * m:j * m + m + 1]

        def poly(x):
            total = 0.0
            for a in range(m + 1):
                l = 1.0
                for b in range(m + 1):
                    if b != a:
                        l *= (x - ts[b]) / (ts[a] - ts[b])
                total += ys[a] * l
            return total

        lo, hi = ts[0], ts[-1]
        sign = -1.0 if poly(0.5 * (lo + hi)) < 0 else 1.0
        a, b = lo, hi
        for _ in range(80):
            c, d = b - g * (b - a), a + g * (b - a)
            if sign * poly(c) > sign * poly(d):
                b = d
            else:
                a = c
        best = max(best, abs(poly(0.5 * (a + b))))
    return best


def multipliers(path):
    out = {}
    for line in open(path):
        m = re.match(r"\s*\d+\s+(-?\d+)\s+Multiplier\s+\d+\s+(\S+)\s+(\S+)", line)
        if m:
            out.setdefault(abs(int(m.group(1))), []).append(
                complex(number(m.group(2)), number(m.group(3))))
    return out


def largest_nontrivial(mu):
    k = min(range(len(mu)), key=lambda i: abs(mu[i] - 1.0))
    return max(abs(v) for i, v in enumerate(mu) if i != k)


def main(argv):
    s_hb, s_po, d_po = argv[:3]
    speeds = [float(v) for v in argv[3:]]
    hb = [s for s in solutions(s_hb) if abs(s["ty"]) == 3]
    for s in hb[:1]:
        print(f"hopf {s['par'][1]:.15e} {1.0 / s['par'][11]:.15e}")
    mult = multipliers(d_po)
    for s in solutions(s_po):
        if abs(s["ty"]) == 5:
            print(f"fold {s['par'][1]:.15e} {collocation_max(s):.15e} {s['par'][11]:.15e}")
        elif abs(s["ty"]) == 4 and any(abs(s["par"][1] - v) < 1e-5 * v for v in speeds):
            u0 = s["u"][0]
            x0 = [1e-3 * v for v in u0[:6]] + [1e-3 * OMS * v for v in u0[6:12]]
            crit = largest_nontrivial(mult[abs(s["pt"])])
            print(f"cycle {s['par'][1]:.15e} {s['par'][11]:.15e} {collocation_max(s):.15e} "
                  f"{crit:.6e} {abs(s['pt'])} " + " ".join(f"{v:.15e}" for v in x0))


if __name__ == "__main__":
    main(sys.argv[1:])
