#!/usr/bin/python3
"""plot_run.py — PNG plots of an sphsolid run directory.

    /usr/bin/python3 tools/plot_run.py RUN_DIR [--out PLOTDIR] [--snapshots K]
                                               [--times t1,t2,...]

Writes, under PLOTDIR (default RUN_DIR/plots):

  timeseries.png         (a) each observer's displacement from its t = 0 position (the
                         component with the largest excursion), (b) kinetic, strain and
                         total energy, (c) linear momentum components and the angular
                         momentum relative error |L(t) - L0| / |L0| where summary.json says it
                         is conserved and L0 != 0 (its max_angular_momentum_error is a number);
                         otherwise |L| itself, with the reason the error is not shown (a
                         constraint, a wall, gravity: "angular_momentum_not_conserved"; no spin;
                         no summary.json), (d) in fluid scenes with wall bodies, the drag and
                         lift coefficients, with the mean C_D over the trailing window of
                         summary.json (force_window_start), on an axis spanning the run after
                         its first tenth where the start's transient reaches beyond it (the
                         printed line says so), all against time; panels without data are
                         left out.
  snapshot_NNNNNN.png    particles at their deformed positions coloured by von Mises stress
                         (or by the first scalar point field present when there is none), one
                         colour scale for all the plotted snapshots; 3D runs are projected
                         onto the plane of their two largest extents; 1D runs (a line of
                         particles) plot the field against x.

Snapshots: K of them (default 4: the first, the last and evenly spaced between; 0: none),
or those nearest the times given with --times.  Only the selected snapshot files are read.

Prints one line per PNG written.  Exit status 2, with a message, when RUN_DIR holds no
timeseries.csv (nor the timeseries.csv.partial of a run that was killed).

The sphsolid binary embeds this file and pipes it to `/usr/bin/python3 - RUN_DIR`, so it
is self-contained: no __file__, no sibling modules.  The run directory layout is described
in docs/output-format.md.
"""
import argparse
import json
import os
import re
import sys

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PROG = "plot_run.py"
DPI = 120
SNAP_WIDTH_IN = 10.0          # snapshot figures are 1200 px wide
TS_SIZE_IN = (9.0, 10.0)      # timeseries figure: 1080 x 1200 px (3 panels)

# point fields tried, in this order, when von_mises is absent (then any other scalar)
SCALAR_PREFERENCE = ["von_mises", "pressure", "density"]
FIELD_LABELS = {
    "von_mises": ("von Mises stress", "Pa"),
    "pressure": ("pressure", "Pa"),
    "density": ("density", "kg/m$^3$"),
}


class UsageError(Exception):
    pass


def fail(msg):
    print(f"{PROG}: error: {msg}", file=sys.stderr)
    sys.exit(2)


# --------------------------------------------------------------------------------------
# run directory
# --------------------------------------------------------------------------------------

def read_timeseries(path):
    """Columns of a timeseries CSV as {name: float array}.  A row with the wrong number of
    fields or an unparsable value (the torn last line of a killed run) ends the table."""
    # UTF-8 whatever the locale: what the writers write (docs/output-format.md)
    with open(path, encoding="utf-8") as f:
        header = f.readline().strip()
        if not header:
            return [], {}
        names = [h.strip() for h in header.split(",")]
        rows = []
        for line in f:
            parts = line.strip().split(",")
            if len(parts) != len(names):
                break
            try:
                rows.append([float(p) for p in parts])
            except ValueError:
                break
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    return names, {n: data[:, k] for k, n in enumerate(names)}


def read_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def observers_of(names):
    """Observer names and their component columns, in file order: every <name>_x/_y[/_z]
    group that is not momentum, angular momentum or a fluid scene's force on its walls."""
    groups = {}
    order = []
    for n in names:
        m = re.fullmatch(r"(.+)_([xyz])", n)
        if not m or m.group(1) in ("momentum", "angular_momentum", "pressure_force",
                                   "viscous_force"):
            continue
        base = m.group(1)
        if base not in groups:
            groups[base] = []
            order.append(base)
        groups[base].append(m.group(2))
    return [(b, groups[b]) for b in order]


def run_title(summary, partial, ts_name):
    parts = []
    if summary:
        scene = summary.get("scene") or {}
        title = scene.get("title") or summary.get("title")
        if title:
            parts.append(str(title))
        detail = []
        for key in ("formulation", "backend", "precision"):
            if summary.get(key):
                detail.append(str(summary[key]))
        if summary.get("particle_count") is not None:
            detail.append(f"{summary['particle_count']} particles")
        if detail:
            parts.append(", ".join(detail))
        status = summary.get("status")
        if status and status != "completed":
            parts.append(f"status: {status}")
    if partial:
        parts.append(f"run incomplete: {ts_name}")
    return " — ".join(parts) if parts else ""


def dimension_of(summary, names):
    try:
        return int(summary["resolved"]["dimension"])
    except (KeyError, TypeError, ValueError):
        pass
    return 3 if "angular_momentum_z" in names or "momentum_z" in names else 2


def dp_of(summary):
    try:
        dp = float(summary["resolved"]["dp"])
        return dp if dp > 0 else None
    except (KeyError, TypeError, ValueError):
        return None


# --------------------------------------------------------------------------------------
# timeseries.png
# --------------------------------------------------------------------------------------

def top_legend(ax, handles=None):
    """The legend in one row above the panel, right of its left-aligned title."""
    if handles is None:
        handles = ax.get_legend_handles_labels()[0]
    ax.legend(handles=handles, loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=len(handles),
              fontsize="small", frameon=False, borderaxespad=0.1, handlelength=1.6,
              columnspacing=1.2)


def angular_momentum_error_shown(summary):
    """(True, None) where |L - L0| / |L0| is an error to plot: summary.json's metrics say
    the scene conserves angular momentum and the body spins; else (False, why).  Where
    something outside the bodies exerts a torque (a clamp, rollers, a driven region, a
    wall, gravity), |L - L0| / |L0| swings through 200 % with the motion: plotted, it would
    read as a 200 % error."""
    if not summary:
        return False, "no summary.json: angular-momentum conservation unknown"
    metrics = summary.get("metrics") or {}
    if "angular_momentum_not_conserved" not in metrics:
        return False, "summary.json does not say whether angular momentum is conserved"
    why = metrics["angular_momentum_not_conserved"]
    if why:
        return False, f"angular momentum not conserved ({why})"
    if metrics.get("max_angular_momentum_error") is None:
        return False, "no spin (L0 = 0)"
    return True, None


def plot_timeseries(names, cols, dim, title, out_path, summary=None):
    t = cols.get("time")
    if t is None or len(t) == 0:
        return None
    unit_e = "J/m" if dim == 2 else "J"
    unit_p = "kg m/s per m" if dim == 2 else "kg m/s"      # 2D: per metre of depth
    unit_l = "kg m$^2$/s per m" if dim == 2 else "kg m$^2$/s"

    panels = []
    summary_bits = []

    # (a) observers
    obs = observers_of(names)
    if obs:
        def draw_obs(ax):
            for name, comps in obs:
                best, best_amp, best_d = None, -1.0, None
                for c in comps:
                    d = cols[f"{name}_{c}"] - cols[f"{name}_{c}"][0]
                    amp = float(np.max(np.abs(d))) if len(d) else 0.0
                    if amp > best_amp:
                        best, best_amp, best_d = c, amp, d
                ax.plot(t, best_d, label=f"{name} {best}")
                summary_bits.append(f"{name} {best} max |displacement| = {best_amp:.6g} m")
            ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
            ax.set_ylabel("displacement [m]")
            top_legend(ax)
        panels.append(("observer displacement from t = 0", draw_obs))

    # (b) energies
    energy_cols = [("kinetic_energy", "kinetic"), ("strain_energy", "strain"),
                   ("total_energy", "total")]
    if any(c in cols for c, _ in energy_cols):
        def draw_energy(ax):
            styles = {"kinetic": "-", "strain": "-", "total": "--"}
            for c, label in energy_cols:
                if c in cols:
                    ax.plot(t, cols[c], styles[label], label=label,
                            color="k" if label == "total" else None)
            ax.set_ylabel(f"energy [{unit_e}]")
            top_legend(ax)
        panels.append(("energy", draw_energy))

    # (c) momentum
    p_cols = [c for c in ("momentum_x", "momentum_y", "momentum_z") if c in cols]
    if dim == 2 and "angular_momentum" in cols:
        L = cols["angular_momentum"][:, None]
    else:
        lc = [c for c in ("angular_momentum_x", "angular_momentum_y", "angular_momentum_z")
              if c in cols]
        L = np.stack([cols[c] for c in lc], axis=1) if lc else None
    if p_cols or L is not None:
        def draw_momentum(ax):
            handles = []
            for c in p_cols:
                handles += ax.plot(t, cols[c], label=f"$p_{c[-1]}$")
            ax.set_ylabel(f"linear momentum [{unit_p}]")
            if L is not None and len(L):
                ax2 = ax.twinx()
                L0 = np.linalg.norm(L[0])
                shown, why = angular_momentum_error_shown(summary)
                if shown and L0 > 0:
                    err = np.linalg.norm(L - L[0], axis=1) / L0
                    handles += ax2.plot(t, err, color="tab:purple", ls="--",
                                        label="$|L - L_0| / |L_0|$")
                    ax2.set_ylabel("angular momentum $|L - L_0| / |L_0|$", color="tab:purple")
                    summary_bits.append(f"max |L - L0|/|L0| = {float(np.max(err)):.3g}")
                else:
                    why = why or "no spin (L0 = 0)"
                    handles += ax2.plot(t, np.linalg.norm(L, axis=1), color="tab:purple",
                                        ls="--", label="$|L|$")
                    ax2.set_ylabel(f"angular momentum |L| [{unit_l}]", color="tab:purple")
                    # on the twin axes, drawn after the first: above every curve
                    ax2.text(0.01, 0.03, f"$|L - L_0| / |L_0|$ not shown: {why}",
                             transform=ax2.transAxes, fontsize="small", color="tab:purple",
                             ha="left", va="bottom", wrap=True, zorder=5,
                             bbox=dict(facecolor="white", edgecolor="none", alpha=0.85))
                    summary_bits.append(f"{why}: |L| plotted, not |L - L0|/|L0|")
                ax2.tick_params(axis="y", colors="tab:purple")
            top_legend(ax, handles)
        panels.append(("momentum", draw_momentum))

    # (d) force coefficients of the wall bodies (fluid scenes with walls)
    if "drag_coefficient" in cols and "lift_coefficient" in cols:
        metrics = (summary or {}).get("metrics", {}) if isinstance(summary, dict) else {}

        def draw_forces(ax):
            handles = ax.plot(t, cols["drag_coefficient"], label="$C_D$")
            handles += ax.plot(t, cols["lift_coefficient"], label="$C_L$")
            start = metrics.get("force_window_start")
            mean_cd = metrics.get("mean_drag_coefficient")
            if isinstance(start, (int, float)) and isinstance(mean_cd, (int, float)):
                ax.axvspan(start, t[-1], color="0.9", zorder=0)
                handles += ax.plot([start, t[-1]], [mean_cd, mean_cd], "k--", lw=0.8,
                                   label=f"mean $C_D$ = {mean_cd:.4g}")
                bits = [f"mean C_D = {mean_cd:.4g} from t = {start:g}"]
                for key, label in (("lift_amplitude", "C_L amplitude"),
                                   ("strouhal_number", "St")):
                    if isinstance(metrics.get(key), (int, float)):
                        bits.append(f"{label} = {metrics[key]:.4g}")
                summary_bits.append(", ".join(bits))
            ax.axhline(0.0, color="0.6", lw=0.6, zorder=0)
            # a flow started from rest or impulsively has a start-up transient many times
            # the settled forces (the cylinder: C_D up to 16 before t = 10 against 1.4
            # after): the axis spans the run after its first tenth, and says what it clips
            t_late = t[0] + 0.1 * (t[-1] - t[0])
            both = np.concatenate([cols["drag_coefficient"], cols["lift_coefficient"]])
            late = np.concatenate([cols["drag_coefficient"][t >= t_late],
                                   cols["lift_coefficient"][t >= t_late]])
            if late.size:
                lo, hi = min(float(late.min()), 0.0), max(float(late.max()), 0.0)
                pad = 0.08 * (hi - lo) if hi > lo else 1.0
                if both.min() < lo - pad or both.max() > hi + pad:
                    ax.set_ylim(lo - pad, hi + pad)
                    summary_bits.append(f"the start before t = {t_late:.3g} clipped (coefficients "
                                        f"{both.min():.3g} to {both.max():.3g})")
            ax.set_ylabel("force coefficient")
            top_legend(ax, handles)
        panels.append(("drag and lift coefficients of the wall bodies", draw_forces))

    if not panels:
        return None
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=(TS_SIZE_IN[0], TS_SIZE_IN[1] * (0.4 + 0.2 * len(panels))),
                             dpi=DPI)
    letters = "abcd"
    for k, ((name, draw), ax) in enumerate(zip(panels, axes[:, 0])):
        draw(ax)
        ax.set_title(f"({letters[k]}) {name}", loc="left", fontsize="medium")
        ax.grid(True, lw=0.4, alpha=0.5)
        ax.set_xlim(t[0], t[-1] if t[-1] > t[0] else t[0] + 1.0)
    axes[-1, 0].set_xlabel("time [s]")
    if title:
        fig.suptitle(title, fontsize="medium")
    fig.tight_layout()
    fig.savefig(out_path, dpi=DPI)
    plt.close(fig)
    return "; ".join(summary_bits) if summary_bits else f"{len(t)} rows"


# --------------------------------------------------------------------------------------
# snapshots
# --------------------------------------------------------------------------------------

def list_snapshots(run_dir):
    """[(time, index, path)] sorted by time: from snapshots.hdf.series when present,
    else from the files in snapshots/ (their times read from /sphsolid/time)."""
    snaps = []
    series = read_json(os.path.join(run_dir, "snapshots.hdf.series"))
    if series and isinstance(series.get("files"), list):
        for entry in series["files"]:
            try:
                name, time = entry["name"], float(entry["time"])
            except (KeyError, TypeError, ValueError):
                continue
            path = os.path.join(run_dir, name)
            if os.path.isfile(path):
                snaps.append((time, snapshot_index(path, len(snaps)), path))
    else:
        sdir = os.path.join(run_dir, "snapshots")
        files = sorted(f for f in os.listdir(sdir) if f.endswith(".hdf")) \
            if os.path.isdir(sdir) else []
        if files:
            import h5py
            for k, f in enumerate(files):
                path = os.path.join(sdir, f)
                try:
                    with h5py.File(path, "r") as h:
                        time = float(h["sphsolid"].attrs["time"])
                except Exception:
                    time = float(k)
                snaps.append((time, snapshot_index(path, k), path))
    snaps.sort(key=lambda s: (s[0], s[1]))
    return snaps


def snapshot_index(path, default):
    m = re.search(r"(\d+)\.hdf$", os.path.basename(path))
    return int(m.group(1)) if m else default


def select_snapshots(snaps, count, times):
    if not snaps:
        return []
    if times:
        st = np.array([s[0] for s in snaps])
        picked = sorted({int(np.argmin(np.abs(st - t))) for t in times})
    else:
        if count <= 0:
            return []
        if count >= len(snaps):
            picked = list(range(len(snaps)))
        elif count == 1:
            picked = [len(snaps) - 1]
        else:
            picked = sorted({int(round(k * (len(snaps) - 1) / (count - 1)))
                             for k in range(count)})
    return [snaps[k] for k in picked]


def read_snapshot(path):
    import h5py
    with h5py.File(path, "r") as h:
        g = h["VTKHDF"]
        pts = np.asarray(g["Points"][()], dtype=float).reshape(-1, 3)
        field = None
        pd = g.get("PointData")
        if pd is not None:
            scalars = [n for n in pd.keys()
                       if isinstance(pd[n], h5py.Dataset) and pd[n].ndim == 1]
            floats = [n for n in scalars if pd[n].dtype.kind == "f"]
            order = [n for n in SCALAR_PREFERENCE if n in floats] + \
                    sorted(n for n in floats if n not in SCALAR_PREFERENCE) + \
                    sorted(n for n in scalars if n not in floats)
            if order:
                field = order[0]
                values = np.asarray(pd[field][()], dtype=float)
        if field is None:
            values = np.zeros(len(pts))
        meta = {}
        s = h.get("sphsolid")
        if s is not None:
            for k in ("time", "parameters"):
                if k in s.attrs:
                    v = s.attrs[k]
                    meta[k] = v.decode() if isinstance(v, bytes) else v
    return pts, field, values, meta


def estimate_dp(pts):
    """Median nearest-neighbour distance over (a sample of) the particles."""
    n = len(pts)
    if n < 2:
        return None
    rng = np.random.default_rng(0)
    sample = pts[rng.choice(n, size=min(n, 1000), replace=False)]
    best = np.full(len(sample), np.inf)
    for start in range(0, n, 4096):
        block = pts[start:start + 4096]
        d2 = ((sample[:, None, :] - block[None, :, :]) ** 2).sum(axis=2)
        d2[d2 <= 0.0] = np.inf
        best = np.minimum(best, d2.min(axis=1))
    best = best[np.isfinite(best)]
    return float(np.sqrt(np.median(best))) if len(best) else None


def plot_line_snapshots(data, title, out_dir):
    """1D runs (a line of particles): the field against x, one scale for every snapshot."""
    finite = np.concatenate([d[5][np.isfinite(d[5])] for d in data])
    vmin = float(finite.min()) if len(finite) else 0.0
    vmax = float(finite.max()) if len(finite) else 1.0
    pad = 0.05 * (vmax - vmin) if vmax > vmin else 0.5
    fig_h = 4.5
    fig, ax = plt.subplots(figsize=(SNAP_WIDTH_IN, fig_h), dpi=DPI)
    written = []
    for time, index, path, pts, field, values, meta in data:
        ax.clear()
        order = np.argsort(pts[:, 0], kind="stable")
        ax.plot(pts[order, 0], values[order], ".-", ms=2.0, lw=0.6)
        name, unit = FIELD_LABELS.get(field, (field or "no field", ""))
        ax.set_ylabel(f"{name} [{unit}]" if unit else name)
        ax.set_xlabel("x [m]")
        ax.set_ylim(vmin - pad, vmax + pad)
        ax.grid(True, lw=0.3, alpha=0.4)
        ax.set_title(f"{title}\nt = {time:.6g} s   (snapshot {index}, {len(pts)} particles)",
                     fontsize="medium")
        fig.tight_layout()
        out = os.path.join(out_dir, f"snapshot_{index:06d}.png")
        fig.savefig(out, dpi=DPI)
        fin = values[np.isfinite(values)]
        vrange = f"[{fin.min():.6g}, {fin.max():.6g}]" if len(fin) else "[]"
        written.append((out, f"t = {time:.6g} s, {field or 'no field'} {vrange}"
                             f"{' ' + unit if unit else ''} against x, "
                             f"{int(SNAP_WIDTH_IN * DPI)}x{int(round(fig_h * DPI))} px"))
    plt.close(fig)
    return written


def plot_snapshots(selected, dim, dp, title, out_dir):
    data = []
    for time, index, path in selected:
        try:
            pts, field, values, meta = read_snapshot(path)
        except Exception as e:                      # an unreadable file: say so, go on
            print(f"{PROG}: warning: cannot read {path}: {e}", file=sys.stderr)
            continue
        if "time" in meta:
            try:
                time = float(meta["time"])
            except (TypeError, ValueError):
                pass
        data.append((time, index, path, pts, field, values, meta))
    if not data:
        return []

    if dim == 1:
        return plot_line_snapshots(data, title, out_dir)

    # projection plane: 2D runs (z = 0) use x-y; 3D runs the two largest extents
    all_pts = np.concatenate([d[3] for d in data])
    lo, hi = all_pts.min(axis=0), all_pts.max(axis=0)
    extent = hi - lo
    is3d = dim == 3 or extent[2] > 0.0
    axes_names = "xyz"
    if is3d:
        plane = sorted(np.argsort(-extent, kind="stable")[:2])
        depth = [a for a in range(3) if a not in plane][0]
    else:
        plane, depth = [0, 1], None

    if dp is None:
        for d in data:
            if d[6].get("parameters"):
                try:
                    dp = float(json.loads(d[6]["parameters"])["dp"])
                    break
                except (ValueError, KeyError, TypeError):
                    pass
    if dp is None or not dp > 0:
        dp = estimate_dp(data[0][3]) or max(float(extent.max()), 1.0) / 100.0

    # one colour scale for every plotted snapshot
    finite = [d[5][np.isfinite(d[5])] for d in data]
    finite = np.concatenate(finite) if finite else np.zeros(1)
    vmin = float(finite.min()) if len(finite) else 0.0
    vmax = float(finite.max()) if len(finite) else 1.0
    if not vmax > vmin:
        vmin, vmax = (vmin - 0.5, vmax + 0.5) if vmin != 0.0 else (0.0, 1.0)

    # one frame for every plotted snapshot: the union of the particles' extents
    x0, x1 = lo[plane[0]], hi[plane[0]]
    y0, y1 = lo[plane[1]], hi[plane[1]]
    pad = max(dp, 0.03 * max(x1 - x0, y1 - y0, dp))
    x0, x1, y0, y1 = x0 - pad, x1 + pad, y0 - pad, y1 + pad

    # figure: fixed width; axes height from the data's aspect ratio, within limits
    left, right, bottom, top = 0.9, 1.55, 0.6, 0.75
    ax_w = SNAP_WIDTH_IN - left - right
    ax_h = min(max(ax_w * (y1 - y0) / (x1 - x0), 2.5), 7.5)
    fig_h = round((ax_h + bottom + top) * DPI / 2) * 2 / DPI
    ax_h = fig_h - bottom - top
    # widen the shorter range so that the frame has the axes' aspect ratio: equal scales
    if (x1 - x0) / (y1 - y0) < ax_w / ax_h:
        grow = 0.5 * ((y1 - y0) * ax_w / ax_h - (x1 - x0))
        x0, x1 = x0 - grow, x1 + grow
    else:
        grow = 0.5 * ((x1 - x0) * ax_h / ax_w - (y1 - y0))
        y0, y1 = y0 - grow, y1 + grow
    # marker diameter: the particle spacing in points, times sqrt(2) (and a little) so that
    # the circles of a square lattice leave no pinholes and the body looks solid
    dp_pts = dp * ax_w / (x1 - x0) * 72.0
    size = max(1.45 * dp_pts, 0.8) ** 2

    # one figure for all the snapshots: only the particles and the texts change
    fig = plt.figure(figsize=(SNAP_WIDTH_IN, fig_h), dpi=DPI)
    ax = fig.add_axes([left / SNAP_WIDTH_IN, bottom / fig_h, ax_w / SNAP_WIDTH_IN, ax_h / fig_h])
    cax = fig.add_axes([(left + ax_w + 0.2) / SNAP_WIDTH_IN, bottom / fig_h,
                        0.22 / SNAP_WIDTH_IN, ax_h / fig_h])
    ax.set_xlim(x0, x1)
    ax.set_ylim(y0, y1)
    ax.set_aspect("equal", adjustable="box")       # already equal: the box does not move
    xl, yl = axes_names[plane[0]], axes_names[plane[1]]
    if is3d:
        ax.set_xlabel(f"{xl} [m]   (projection onto the {xl}-{yl} plane, "
                      f"seen from +{axes_names[depth]})")
    else:
        ax.set_xlabel(f"{xl} [m]")
    ax.set_ylabel(f"{yl} [m]")
    ax.tick_params(labelsize="small")
    ax.grid(True, lw=0.3, alpha=0.4)
    ax.set_axisbelow(True)
    sc = ax.scatter(np.zeros(0), np.zeros(0), c=np.zeros(0), s=size, marker="o",
                    linewidths=0, cmap="turbo", vmin=vmin, vmax=vmax)
    cb = fig.colorbar(sc, cax=cax)
    cb.formatter.set_powerlimits((-3, 4))
    cb.update_ticks()
    fig.text(0.5, 1.0 - 0.12 / fig_h, title, ha="center", va="top", fontsize="medium")
    head_text = fig.text(0.5, 1.0 - 0.42 / fig_h, "", ha="center", va="top",
                         fontsize="medium")

    written = []
    for time, index, path, pts, field, values, meta in data:
        # 3D: the particles nearest the viewer (largest depth coordinate) drawn last
        order = np.argsort(pts[:, depth], kind="stable") if depth is not None \
            else slice(None)
        sc.set_offsets(np.column_stack([pts[order, plane[0]], pts[order, plane[1]]]))
        sc.set_array(values[order])
        if field is None:
            label = "(no scalar point field: uniform colour)"
        else:
            name, unit = FIELD_LABELS.get(field, (field, ""))
            label = f"{name} [{unit}]" if unit else name
            if field != "von_mises":
                label += "  (von_mises absent)"
        cb.set_label(label)
        head_text.set_text(f"t = {time:.6g} s   (snapshot {index}" +
                           ("" if "particles" in title else f", {len(pts)} particles") + ")")
        out = os.path.join(out_dir, f"snapshot_{index:06d}.png")
        fig.savefig(out, dpi=DPI)
        fin = values[np.isfinite(values)]
        vrange = (f"[{fin.min():.6g}, {fin.max():.6g}]" if len(fin) else "[]")
        unit = FIELD_LABELS.get(field, ("", ""))[1] if field else ""
        desc = (f"t = {time:.6g} s, {field or 'no field'} {vrange}"
                f"{' ' + unit if unit else ''} "
                f"(colour scale [{vmin:.6g}, {vmax:.6g}]), "
                f"{int(SNAP_WIDTH_IN * DPI)}x{int(round(fig_h * DPI))} px")
        written.append((out, desc))
    plt.close(fig)
    return written


# --------------------------------------------------------------------------------------

def parse_args(argv):
    ap = argparse.ArgumentParser(prog=PROG, description="PNG plots of an sphsolid run "
                                 "directory (timeseries and particle snapshots).")
    ap.add_argument("run_dir", metavar="RUN_DIR")
    ap.add_argument("--out", metavar="PLOTDIR", help="where the PNGs go (RUN_DIR/plots)")
    ap.add_argument("--snapshots", metavar="K", type=int, default=4,
                    help="plot K snapshots: first, last and evenly spaced between "
                         "(default 4; 0: none)")
    ap.add_argument("--times", metavar="t1,t2,...",
                    help="plot the snapshots nearest these times (instead of --snapshots)")
    args = ap.parse_args(argv)
    if args.times is not None:
        try:
            args.times = [float(x) for x in args.times.split(",") if x.strip()]
        except ValueError:
            ap.error(f"--times: expected comma-separated numbers, got {args.times!r}")
        if not args.times:
            ap.error("--times: no times given")
    if args.snapshots < 0:
        ap.error("--snapshots: K must be >= 0")
    return args


def main(argv):
    args = parse_args(argv)
    run_dir = args.run_dir
    if not os.path.isdir(run_dir):
        fail(f"{run_dir}: no such run directory")
    ts_path = os.path.join(run_dir, "timeseries.csv")
    partial = False
    if not os.path.isfile(ts_path):
        ts_path += ".partial"
        partial = True
        if not os.path.isfile(ts_path):
            fail(f"{run_dir}: no timeseries.csv (nor timeseries.csv.partial): "
                 f"not an sphsolid run directory, or the run wrote no output yet")
    summary = read_json(os.path.join(run_dir, "summary.json"))
    names, cols = read_timeseries(ts_path)
    dim = dimension_of(summary, names)
    title = run_title(summary, partial, os.path.basename(ts_path))

    out_dir = args.out or os.path.join(run_dir, "plots")
    os.makedirs(out_dir, exist_ok=True)

    out = os.path.join(out_dir, "timeseries.png")
    desc = plot_timeseries(names, cols, dim, title, out, summary)
    if desc is None:
        print(f"{PROG}: warning: {ts_path} has no rows: no timeseries plot", file=sys.stderr)
    else:
        print(f"{out}: {desc}")

    if args.times or args.snapshots > 0:
        snaps = list_snapshots(run_dir)
        selected = select_snapshots(snaps, args.snapshots, args.times)
        if selected:
            for path, desc in plot_snapshots(selected, dim, dp_of(summary), title, out_dir):
                print(f"{path}: {desc}")
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
