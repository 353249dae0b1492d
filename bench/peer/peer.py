#!/usr/bin/env python3
"""Helpers of bench/peer/run.sh (the glass plate in LAMMPS peridynamics next to brittle).

Python 3 standard library, numpy and matplotlib (Debian: python3-numpy, python3-matplotlib).

  peer.py params  --h H [--L ... see --help]   the PMB constants, time step and loads, as
                                                KEY=VALUE lines for the shell (and params.json)
  peer.py lammps-metrics LOG TIME_V DUMP_DIR PARAMS.json OUT.json
  peer.py brittle-metrics RUN_DIR TIME_V OUT.json
  peer.py picture --brittle PNG --lammps DUMP TITLE [--lammps DUMP TITLE ...] --params P.json
                  --out PNG [--title T]
  peer.py table OUT_DIR                         OUT_DIR/peer.md from every */*/metrics.json

The peridynamic model (docs/peer.md says why):
  one layer of atoms on a simple cubic lattice of spacing h (atoms at cell centres, so no
  atom lies on the crack plane y = 0), each standing for the volume V = h^2 T of the plate;
  bond-based PMB (Silling 2000; LAMMPS pair_style peri/pmb), calibrated as a 2D plane-stress
  model (Ha & Bobaru 2010), which fixes Poisson's ratio at 1/3:
      c  = 9 E / (pi T delta^3),   s0 = sqrt(4 pi G_c / (9 E delta))        (continuum)
  (Derivation: a bond's energy is c s^2 |xi| / 2 per unit volume squared. Under in-plane
  isotropic stretch s the energy density is (1/2) int_0^delta (c s^2 xi / 2) T 2 pi xi dxi
  = pi c s^2 T delta^3 / 6, and plane stress with nu = 1/3 gives E s^2 / (1 - nu) = 1.5 E s^2,
  hence c. Breaking every bond across a unit area of crack costs
  2 int_0^delta int_z^delta int_0^acos(z/xi) (c s0^2 xi / 2) T xi dtheta dxi dz
  = c s0^2 T delta^4 / 4 = G_c, hence s0.)
  The script uses the lattice's own sums instead (same horizon, same partial-volume factor
  as LAMMPS's pair_peri_pmb.cpp), so that the discrete plate has exactly E under in-plane
  isotropic stretch and exactly G_c across the crack plane y = 0:
      c  = 6 E / sum_j |xi_j| V beta_j
      s0 = sqrt(2 G_c h T / (c V^2 sum_{i above, j below, one column} |xi_ij| beta_ij))
  with beta the partial-volume factor of bonds within h/2 of the horizon.
  Stable time step (Silling & Askari 2005): dt_crit = sqrt(2 rho / sum_j V beta_j c / |xi_j|).
"""

import argparse
import glob
import json
import math
import os
import re
import sys


# ---------------------------------------------------------------------------------------------
# params


def lattice_offsets(m_max):
    r = range(-m_max, m_max + 1)
    return [(p, q) for p in r for q in r if (p, q) != (0, 0)]


def partial_volume(r0, delta, h):
    """LAMMPS pair_peri_pmb.cpp: vfrac_scale for a bond of reference length r0."""
    half = 0.5 * h
    if abs(r0 - delta) <= half:
        return (-1.0 / (2 * half)) * r0 + (1.0 + ((delta - half) / (2 * half)))
    return 1.0


def pmb_params(a):
    h, T, E, G, rho = a.h, a.T, a.E, a.Gc, a.rho
    delta = a.m * h
    V = h * h * T
    m_max = int(math.ceil(a.m)) + 1
    # family of an interior atom (one layer: in-plane offsets only); LAMMPS bonds rsq <= delta^2
    sum_xi = 0.0       # sum |xi| V beta
    sum_inv = 0.0      # sum V beta / |xi|
    n_family = 0
    for p, q in lattice_offsets(m_max):
        r0 = h * math.hypot(p, q)
        if r0 * r0 <= delta * delta:
            b = partial_volume(r0, delta, h)
            sum_xi += r0 * V * b
            sum_inv += V * b / r0
            n_family += 1
    c = 6.0 * E / sum_xi
    # bonds across y = 0 for one column of atoms above the plane (x = 0, y = (k + 1/2) h)
    sum_cross = 0.0
    for k in range(m_max + 1):
        for kk in range(m_max + 1):
            dy = (k + kk + 1) * h
            for p in range(-m_max, m_max + 1):
                r0 = math.hypot(p * h, dy)
                if r0 * r0 <= delta * delta:
                    sum_cross += r0 * partial_volume(r0, delta, h)
    s0 = math.sqrt(2.0 * G * h * T / (c * V * V * sum_cross))
    c_cont = 9.0 * E / (math.pi * T * delta ** 3)
    s0_cont = math.sqrt(4.0 * math.pi * G / (9.0 * E * delta))
    # 3D PMB (the brief's formulas), for the record: kappa from E, nu
    kappa = E / (3.0 * (1.0 - 2.0 * a.nu))
    c_3d = 18.0 * kappa / (math.pi * delta ** 4)
    s0_3d = math.sqrt(5.0 * G / (9.0 * kappa * delta))
    dt_crit = math.sqrt(2.0 * rho / (c * sum_inv))
    if a.dt > 0:
        dt_target = a.dt
    else:
        dt_target = a.safety * dt_crit
    # whole number of steps to end_time, a multiple of the number of dumps
    n_dumps = a.dumps
    nsteps = int(math.ceil(a.end / dt_target / n_dumps)) * n_dumps
    dt = a.end / nsteps
    # traction on the edge row: force per atom t * h * T; LAMMPS PERI forces are force
    # densities (f / rmass with rmass = density), so the per-atom value is t h T / V = t / h
    fdens = a.traction / h
    nx = int(round(a.L / h))
    ny = int(round(a.Hplate / h))
    # plane-stress wave speeds of the PMB plate (nu = 1/3) and of glass (nu = a.nu)
    nu_pmb = 1.0 / 3.0
    cp_pmb = math.sqrt(E / (rho * (1 - nu_pmb ** 2)))
    cp_glass = math.sqrt(E / (rho * (1 - a.nu ** 2)))
    return {
        "h": h, "delta": delta, "horizon_factor": a.m, "V": V, "T": T, "L": a.L,
        "H": a.Hplate, "notch": a.notch, "rho": rho, "E": E, "nu_pmb": nu_pmb,
        "nu_glass": a.nu, "G_c": G,
        "c": c, "s0": s0, "c_continuum": c_cont, "s0_continuum": s0_cont,
        "c_3d_brief": c_3d, "s0_3d_brief": s0_3d, "kappa": kappa,
        "family_size": n_family, "dt_crit": dt_crit, "dt": dt, "nsteps": nsteps,
        "dump_every": nsteps // n_dumps, "thermo_every": max(1, int(round(1e-6 / dt))),
        "end_time": a.end, "traction": a.traction,
        "force_density": fdens, "atoms_expected": nx * ny,
        "cp_plane_stress_pmb": cp_pmb, "cp_plane_stress_glass": cp_glass,
        "dt_over_h_cp": dt / (h / cp_pmb),
    }


def cmd_params(argv):
    p = argparse.ArgumentParser(prog="peer.py params")
    p.add_argument("--h", type=float, required=True, help="lattice spacing [m]")
    p.add_argument("--m", type=float, default=3.015, help="horizon / spacing")
    p.add_argument("--L", type=float, default=100e-3)
    p.add_argument("--H", dest="Hplate", type=float, default=40e-3)
    p.add_argument("--T", type=float, default=0.5e-3)
    p.add_argument("--notch", type=float, default=50e-3)
    p.add_argument("--E", type=float, default=32e9)
    p.add_argument("--nu", type=float, default=0.2)
    p.add_argument("--rho", type=float, default=2450.0)
    p.add_argument("--Gc", type=float, default=3.0)
    p.add_argument("--traction", type=float, default=1e6)
    p.add_argument("--end", type=float, default=80e-6)
    p.add_argument("--safety", type=float, default=0.8, help="dt / dt_crit")
    p.add_argument("--dt", type=float, default=0.0, help="force this time step [s]")
    p.add_argument("--dumps", type=int, default=8, help="damage dumps over the run")
    p.add_argument("--json", help="also write the values here")
    a = p.parse_args(argv)
    r = pmb_params(a)
    if a.json:
        with open(a.json, "w") as f:
            json.dump(r, f, indent=1)
    for k, v in r.items():
        print("P_%s=%r" % (k, v))


# ---------------------------------------------------------------------------------------------
# metrics


def time_v(path):
    """Wall seconds, peak RSS [kB] and CPU seconds (user + system) from /usr/bin/time -v."""
    wall, rss, cpu = float("nan"), float("nan"), 0.0
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line.startswith("User time (seconds)") or line.startswith("System time (seconds)"):
                cpu += float(line.split(":")[1])
            if line.startswith("Elapsed (wall clock) time"):
                t = line.split("):", 1)[1].strip() if "):" in line else line.rsplit(" ", 1)[1]
                parts = [float(x) for x in t.split(":")]
                wall = 0.0
                for x in parts:
                    wall = wall * 60 + x
            elif line.startswith("Maximum resident set size"):
                rss = float(line.split(":")[1])
    return wall, rss, cpu


def read_dump(path):
    """LAMMPS dump custom text file: columns dict of numpy arrays, and the timestep."""
    import numpy as np
    with open(path) as f:
        lines = f.read().splitlines()
    step = int(lines[lines.index("ITEM: TIMESTEP") + 1])
    i = next(k for k, l in enumerate(lines) if l.startswith("ITEM: ATOMS"))
    names = lines[i].split()[2:]
    data = np.loadtxt(lines[i + 1:], ndmin=2)
    return step, {n: data[:, k] for k, n in enumerate(names)}


def last_dump(dump_dir):
    files = glob.glob(os.path.join(dump_dir, "damage.*.txt"))
    if not files:
        return None
    return max(files, key=lambda s: int(re.search(r"damage\.(\d+)\.txt$", s).group(1)))


def classify_damage(cols, notch, h, delta, threshold=0.35):
    """'branched', 'straight' or 'none' from the damage of the atoms right of the notch tip.

    A column of atoms (x > notch + 2 delta) has a crack where its damaged atoms (damage >=
    threshold) form runs along y; 'branched' when some columns have two runs more than
    2 delta apart (two cracks side by side), else 'straight' when damage reaches past the
    notch, else 'none'. Also the crack's reach (largest x of a damaged atom) and the largest
    |y| of a damaged atom right of the notch.
    """
    import numpy as np
    # positions are the dumped (deformed) ones; at 80 us they differ from the lattice by well
    # under a lattice spacing away from the crack faces
    ref_x, ref_y, d = cols["x"], cols["y"], cols["c_dmg"]
    hit = d >= threshold
    right = ref_x > notch + 0.5 * h
    sel = hit & right
    if not sel.any():
        return {"pattern": "none", "reach_x": notch, "max_abs_y": 0.0, "split_columns": 0}
    reach = float(ref_x[sel].max())
    ymax = float(np.abs(ref_y[sel]).max())
    split_x = []
    xs = np.unique(np.round(ref_x[sel & (ref_x > notch + 2 * delta)] / h).astype(int))
    for ix in xs:
        col = sel & (np.round(ref_x / h).astype(int) == ix)
        ys = np.sort(ref_y[col])
        if len(ys) > 1 and (np.diff(ys) > 2 * delta).any():
            split_x.append(ix * h)
    pattern = "branched" if len(split_x) >= max(3, int(round(2e-3 / h))) else "straight"
    return {"pattern": pattern, "reach_x": reach, "max_abs_y": ymax,
            "split_columns": len(split_x),
            "branch_x": min(split_x) if split_x else None}


def thermo_history(text):
    """The thermo table of a LAMMPS log: list of dicts (Step, Time, c_reach, c_spread, ...)."""
    rows, names = [], None
    for line in text.splitlines():
        if line.startswith("Step ") and "c_reach" in line:
            names = line.split()
            continue
        if names is not None:
            if line.startswith("Loop time"):
                break
            parts = line.split()
            try:
                rows.append({n: float(v) for n, v in zip(names, parts)})
            except ValueError:
                continue
    return rows


def crack_history(rows, notch, h):
    """Start, branching and speed of the peridynamic crack from the thermo rows.

    start: the damage (>= 0.35) first reaches 1 mm past the notch tip; branching: damage first
    2 mm or more off the crack line (a straight crack's damage >= 0.35 is the two rows of atoms
    at |y| = h/2); speed: least-squares slope of the reach over time from the start to
    branching (the reach then follows the arms' x).
    """
    start = next((r["Time"] for r in rows if r["c_reach"] > notch + 1e-3), None)
    branch = next((r for r in rows if r["c_spread"] >= 2e-3), None)
    speed = None
    if start is not None:
        t_end = branch["Time"] if branch else rows[-1]["Time"]
        pts = [(r["Time"], r["c_reach"]) for r in rows if start <= r["Time"] <= t_end]
        if len(pts) >= 3:
            n = len(pts)
            mt = sum(p[0] for p in pts) / n
            mx = sum(p[1] for p in pts) / n
            stt = sum((p[0] - mt) ** 2 for p in pts)
            speed = sum((p[0] - mt) * (p[1] - mx) for p in pts) / stt
    return {"start_time": start,
            "branch_time": branch["Time"] if branch else None,
            "branch_reach_x": branch["c_reach"] if branch else None,
            "speed_before_branching": speed}


def cmd_lammps_metrics(argv):
    log, tv, dump_dir, params, out = argv
    with open(params) as f:
        P = json.load(f)
    text = open(log).read()
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    loop, procs, steps, atoms = float(m.group(1)), int(m.group(2)), int(m.group(3)), int(m.group(4))
    b = re.search(r"total # of bonds = (\d+)", text)
    partner_entries = int(b.group(1)) if b else 0
    bonds = partner_entries // 2
    wall, rss, cpu = time_v(tv)
    dump = last_dump(dump_dir)
    cls = {"pattern": "?"}
    tstep = None
    if dump:
        tstep, cols = read_dump(dump)
        cls = classify_damage(cols, P["notch"], P["h"], P["delta"])
    rows = thermo_history(text)
    with open(os.path.join(os.path.dirname(out), "crack.csv"), "w") as f:
        f.write("time,reach_x,spread_y,max_damage\n")
        for row in rows:
            f.write("%.6g,%.6g,%.6g,%.6g\n" % (row["Time"], row["c_reach"], row["c_spread"],
                                              row["c_max_dmg"]))
    cls.update(crack_history(rows, P["notch"], P["h"]))
    r = {
        "code": "LAMMPS %s" % (re.search(r"LAMMPS \(([^)]*)\)", text).group(1)),
        "method": "bond-based peridynamics (PMB, 2D plane stress, nu = 1/3), delta = %.4g h" % P["horizon_factor"],
        "h": P["h"], "nodes": atoms, "elements": bonds, "elements_kind": "bonds",
        "steps": steps, "dt": P["dt"], "dt_crit": P["dt_crit"], "procs": procs,
        "loop_time": loop, "wall": wall, "cpu": cpu, "peak_rss_kB": rss,
        "updates_per_s": atoms * steps / loop, "updates_kind": "atom-steps/s",
        "bond_updates_per_s": bonds * steps / loop,
        "pattern": cls.get("pattern"), "pattern_detail": cls,
        "final_dump": dump, "final_step": tstep,
    }
    with open(out, "w") as f:
        json.dump(r, f, indent=1)
    print(json.dumps(r, indent=1))


def cmd_brittle_metrics(argv):
    run_dir, tv, out = argv
    with open(os.path.join(run_dir, "summary.json")) as f:
        S = json.load(f)
    wall, rss, cpu = time_v(tv)
    branchings = S.get("branchings") or []
    nb = len(branchings) if isinstance(branchings, list) else int(branchings)
    steps = S.get("steps")
    end = S.get("time") or S.get("end_time")
    scene = S.get("scene") or {}
    two_d = str(scene.get("mesh.dimension", 3)) == "2"  # a 2D body of triangles (issue 53)
    kind = "triangles" if two_d else "tets"
    element = ("linear triangles, plane %s" % scene.get("material.plane", "strain")) if two_d \
        else "linear tets"
    r = {
        "code": "brittle %s (%s)" % (S.get("brittle_version", ""),
                                     (S.get("build") or {}).get("commit", "?")),
        "method": "explicit FE (%s), node splitting at sigma_c + cohesive links (Block et al. 2006)"
                  % element,
        "nodes": S.get("nodes"), "elements": S.get("tets"), "elements_kind": kind,
        "steps": steps,
        # the step is set by the smallest element (run.cfl); the mean step lands on 80 us
        "dt": end / steps if steps else None, "dt_initial": S.get("dt"),
        "dt_final": S.get("final_dt"), "procs": 1, "threads": S.get("threads"),
        "loop_time": S.get("wall_seconds"), "wall": wall, "cpu": cpu, "peak_rss_kB": rss,
        "updates_per_s": S.get("tet_updates_per_second"),
        "updates_kind": "triangle-updates/s" if two_d else "tet-updates/s",
        "phases": S.get("phases"), "splits": S.get("splits"), "branchings": nb,
        "nucleations": len(S.get("nucleated_cracks") or []),
        "tip_x": S.get("tip_x"), "tip_y": S.get("tip_y"), "crack_speed": S.get("crack_speed"),
        "cut_through": S.get("cut_through"),
        "pattern": "branched" if nb > 0 else ("straight" if (S.get("splits") or 0) > 0 else "none"),
        "cfl": (S.get("scene") or {}).get("run.cfl"),
    }
    with open(out, "w") as f:
        json.dump(r, f, indent=1)
    print(json.dumps(r, indent=1))


# ---------------------------------------------------------------------------------------------
# picture


def cmd_picture(argv):
    p = argparse.ArgumentParser(prog="peer.py picture")
    p.add_argument("--brittle", required=True, help="brittle's crack frame (PNG)")
    p.add_argument("--brittle-title", default="brittle")
    p.add_argument("--lammps", nargs=2, action="append", required=True,
                   metavar=("DUMP", "TITLE"), help="a damage dump and its title (repeatable)")
    p.add_argument("--params", required=True, help="params.json of the LAMMPS run")
    p.add_argument("--out", required=True)
    p.add_argument("--title", default="")
    a = p.parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.image as mpimg
    with open(a.params) as f:
        P = json.load(f)
    n = 1 + len(a.lammps)
    fig, axes = plt.subplots(1, n, figsize=(6.6 * n, 3.9))
    img = mpimg.imread(a.brittle)
    axes[0].imshow(img)
    axes[0].set_axis_off()
    axes[0].set_title(a.brittle_title, fontsize=10)
    L, H, h = P["L"] * 1e3, P["H"] * 1e3, P["h"] * 1e3
    for ax, (dump, title) in zip(axes[1:], a.lammps):
        step, cols = read_dump(dump)
        x, y, d = cols["x"] * 1e3, cols["y"] * 1e3, cols["c_dmg"]
        order = d.argsort()
        ax.set_aspect("equal")
        ax.set_xlim(-2, L + 2)
        ax.set_ylim(-H / 2 - 2, H / 2 + 2)
        ax.set_xlabel("x [mm] (deformed positions)")
        ax.set_ylabel("y [mm]")
        ax.set_title(title, fontsize=10)
        fig.tight_layout()
        # a square marker one lattice cell wide (plus a little, to close the gaps)
        bbox = ax.get_window_extent().transformed(fig.dpi_scale_trans.inverted())
        side_pt = 1.25 * h / (L + 4) * bbox.width * 72.0
        sc = ax.scatter(x[order], y[order], c=d[order], s=side_pt ** 2, marker="s",
                        linewidths=0, cmap="inferno_r", vmin=0.0, vmax=0.6)
        ax.plot([0, P["notch"] * 1e3], [0, 0], color="tab:blue", lw=0.8)
        cb = fig.colorbar(sc, ax=ax, fraction=0.025, pad=0.02)
        cb.set_label("damage (broken-bond fraction)", fontsize=8)
    if a.title:
        fig.suptitle(a.title, fontsize=11)
    fig.savefig(a.out, dpi=130, bbox_inches="tight")
    print(a.out)


# ---------------------------------------------------------------------------------------------
# table


def fmt_si(v, unit="", digits=3):
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    return ("%." + str(digits) + "g %s") % (v, unit)


def fmt_int(v):
    return "-" if v is None else "{:,}".format(int(v))


def fmt_rate(v):
    if v is None:
        return "-"
    return "%.3g M" % (v / 1e6)


def pattern_cell(r, png):
    d = r.get("pattern_detail", {})
    if r["elements_kind"] != "bonds":  # brittle's (tets or triangles)
        text = r.get("pattern", "?")
        text += " (%s splits, %d branchings" % (fmt_int(r.get("splits")), r.get("branchings") or 0)
        ct = r.get("cut_through")
        if isinstance(ct, dict) and ct.get("t") is not None:
            text += "; reaches x = %.0f mm at %.1f us" % (ct["x"] * 1e3, ct["t"] * 1e6)
        text += ")"
    else:
        text = d.get("pattern", r.get("pattern", "?"))
        parts = []
        if d.get("start_time") is not None:
            parts.append("starts %.0f us" % (d["start_time"] * 1e6))
        if d.get("branch_time") is not None:
            parts.append("2 mm off the line at %.0f us, x = %.0f mm" % (
                d["branch_time"] * 1e6, d["branch_reach_x"] * 1e3))
        if "reach_x" in d:
            parts.append("at 80 us to x = %.0f mm, y = +-%.0f mm" % (d["reach_x"] * 1e3,
                                                                     d["max_abs_y"] * 1e3))
        if parts:
            text += " (" + "; ".join(parts) + ")"
    return "%s, [picture](%s)" % (text, png)


def cmd_table(argv):
    out_dir = argv[0]
    rows = []
    for path in sorted(glob.glob(os.path.join(out_dir, "*", "*", "metrics.json"))):
        with open(path) as f:
            r = json.load(f)
        r["_dir"] = os.path.relpath(os.path.dirname(path), out_dir)
        rows.append(r)
    # by resolution (coarse first), then brittle, LAMMPS, LAMMPS at brittle's dt
    order = {"brittle": 0, "lammps": 1, "lammps-matched-dt": 2}
    rows.sort(key=lambda r: (-float(r["_dir"].split(os.sep)[0][1:-2]),
                             order.get(r["_dir"].split(os.sep)[1], 9)))
    lines = [
        "# The glass plate in LAMMPS peridynamics and in brittle",
        "",
        "Written by bench/peer/run.sh; how to read it: docs/peer.md. One thread / one process",
        "each, one run at a time, under nice -n 19. Wall to 80 us: brittle's summary.json",
        "`wall_seconds` (stepping, without meshing and output) and LAMMPS's `Loop time`; whole",
        "process (wall, user + system CPU) and peak RSS: /usr/bin/time -v.",
        "",
        "| code | method | resolution | nodes / atoms | elements / bonds | steps | dt | wall to 80 us (stepping) | whole process: wall / CPU | peak RSS | updates/s | crack pattern |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        res, kind = r["_dir"].split(os.sep)[0], r["_dir"].split(os.sep)[1]
        if r["elements_kind"] == "bonds":
            rate = "%s atom-steps/s; %s bond-updates/s" % (fmt_rate(r["updates_per_s"]),
                                                          fmt_rate(r["bond_updates_per_s"]))
            dt = "%.3g ns (%.2f of its stable step)" % (r["dt"] * 1e9, r["dt"] / r["dt_crit"])
            code = r["code"] + (", at brittle's dt" if kind == "lammps-matched-dt" else "")
        else:
            rate = "%s %s" % (fmt_rate(r["updates_per_s"]), r.get("updates_kind", "tet-updates/s"))
            dt = "%.3g ns (mean; cfl %s of its stable step)" % (r["dt"] * 1e9, r.get("cfl", "?"))
            code = r["code"]
        lines.append("| %s | %s | h = %s mm | %s | %s %s | %s | %s | %s | %s | %.0f MB | %s | %s |" % (
            code, r["method"], res[1:-2], fmt_int(r["nodes"]), fmt_int(r["elements"]),
            r["elements_kind"], fmt_int(r["steps"]), dt,
            fmt_si(r["loop_time"], "s"), fmt_si(r["wall"], "s") + " / " + fmt_si(r.get("cpu"), "s"),
            r["peak_rss_kB"] / 1024.0, rate, pattern_cell(r, os.path.join(res, "side_by_side.png"))))
    lines.append("")
    with open(os.path.join(out_dir, "peer.md"), "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


def main():
    if len(sys.argv) < 2 or sys.argv[1] in ("-h", "--help"):
        print(__doc__)
        return 0
    cmd, argv = sys.argv[1], sys.argv[2:]
    {"params": cmd_params, "lammps-metrics": cmd_lammps_metrics,
     "brittle-metrics": cmd_brittle_metrics, "picture": cmd_picture,
     "table": cmd_table}[cmd](argv)
    return 0


if __name__ == "__main__":
    sys.exit(main())
