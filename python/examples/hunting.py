"""Example: a bifurcation diagram and a stiffness map with matplotlib.

    pip install ./python matplotlib
    python python/examples/hunting.py [--nonlinear] [--out docs/images/python-example.png]

Left: the hunting limit cycles of a wheelset whose flange contact folds the branch back
(studies/flange-hysteresis.toml; ``--branch STUDY`` for another): lateral amplitude against speed, stable cycles solid, unstable dashed, with the linear (Kalker)
critical speed V_L, the creep law's Hopf speed V_H and the nonlinear critical speed V_NL.
Right: the linear critical speed over the primary stiffnesses (the sweep of
studies/seed-stiffness-map.toml), with the operating speed as a contour; ``--nonlinear`` maps
V_NL instead (the whole sweep with continuations: minutes instead of seconds).

Run from the repository's root (the study paths are relative to it).
"""

import argparse
import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import critspeed  # noqa: E402


def bifurcation_panel(ax, study):
    br = critspeed.bifurcation(study)
    b = br["branch"]
    v, amp, stable = b["speed_m_s"], b["amplitude_y_m"] * 1e3, b["stable"]
    # draw runs of equal stability as separate lines (solid stable, dashed unstable)
    start = 0
    for k in range(1, len(v) + 1):
        if k == len(v) or stable[k] != stable[start]:
            sl = slice(max(start - 1, 0), k)
            ax.plot(v[sl] * 3.6, amp[sl], "-" if stable[start] else "--", color="C0",
                    label=("stable cycles" if stable[start] else "unstable cycles"))
            start = k
    marks = [
        (br["kalker_critical_speed_m_s"], "V_L (Kalker)", "C3"),
        (br["hopf_speed_m_s"], "V_H (Shen)", "C1"),
        (br["nonlinear_critical_speed_m_s"], "V_NL", "C2"),
    ]
    for speed, label, color in marks:
        if speed is not None:
            ax.axvline(speed * 3.6, color=color, lw=1, ls=":",
                       label=f"{label} = {speed * 3.6:.1f} km/h")
    handles, labels = ax.get_legend_handles_labels()
    seen = dict(zip(labels, handles))  # one legend entry per label
    ax.legend(seen.values(), seen.keys(), fontsize=8, loc="upper left")
    ax.set_xlabel("speed (km/h)")
    ax.set_ylabel("lateral amplitude (mm)")
    ax.set_title(f"hunting cycles of '{br['study']}'", fontsize=10)
    return br


def stiffness_panel(fig, ax, study, nonlinear):
    d = critspeed.check(study)  # the resolved study as a dict: edit it, run it
    if not nonlinear:
        d["sweep"]["compute"] = ["kalker"]
    result = "nonlinear_critical_speed_m_s" if nonlinear else "kalker_critical_speed_m_s"
    s = critspeed.sweep(d)
    kx = s["suspension.longitudinal_stiffness_n_per_m"]
    ky = s["suspension.lateral_stiffness_n_per_m"]
    xs, ys = np.unique(kx), np.unique(ky)
    # point ids run over the first axis fastest: reshape to (lateral, longitudinal)
    grid = np.full((len(ys), len(xs)), np.nan)
    grid[np.searchsorted(ys, ky), np.searchsorted(xs, kx)] = s[result] * 3.6
    # points above the speed range (stable up to its top) have no value: drawn grey
    above = s["stable_up_to_m_s"]
    ax.set_facecolor("0.85")
    mesh = ax.pcolormesh(xs / 1e3, ys / 1e3, np.ma.masked_invalid(grid), shading="nearest",
                         cmap="viridis")
    if np.isfinite(above).any():
        ax.text(0.98, 0.97, f"grey: stable up to {np.nanmin(above) * 3.6:.0f} km/h",
                transform=ax.transAxes, ha="right", va="top", fontsize=8)
    ax.set_xscale("log")
    ax.set_yscale("log")
    operating = 200.0
    ax.contour(xs / 1e3, ys / 1e3, grid, levels=[operating], colors="w", linewidths=1.5)
    fig.colorbar(mesh, ax=ax, label=("V_NL" if nonlinear else "V_L") + " (km/h)")
    ax.set_xlabel("longitudinal primary stiffness (N/mm)")
    ax.set_ylabel("lateral primary stiffness (N/mm)")
    ax.set_title(f"{'nonlinear' if nonlinear else 'linear'} critical speed; "
                 f"white: {operating:.0f} km/h", fontsize=10)
    return s


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--nonlinear", action="store_true", help="map V_NL (slow) instead of V_L")
    p.add_argument("--branch", default="studies/flange-hysteresis.toml",
                   help="study of the bifurcation diagram")
    p.add_argument("--out", default="out/python-example.png", help="PNG file to write")
    a = p.parse_args()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    t = time.perf_counter()
    br = bifurcation_panel(left, a.branch)
    t_bif = time.perf_counter() - t
    t = time.perf_counter()
    s = stiffness_panel(fig, right, "studies/seed-stiffness-map.toml", a.nonlinear)
    t_map = time.perf_counter() - t
    import os

    os.makedirs(os.path.dirname(a.out) or ".", exist_ok=True)
    fig.savefig(a.out, dpi=80)
    print(f"{br['cycles']} cycles in {t_bif:.2f} s, {len(s['point_id'])} sweep points "
          f"in {t_map:.2f} s; wrote {a.out}")


if __name__ == "__main__":
    main()
