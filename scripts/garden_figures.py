#!/usr/bin/python3
"""garden_figures.py — the paper's navigation figures from a garden run's telemetry.

Usage: scripts/garden_figures.py LOG.csv OUTDIR [--level levels/garden]

LOG.csv is what `treelearn play levels/garden --autopilot --log LOG.csv` writes (50 Hz; the garden columns after the
centre-of-mass ones). Writes into OUTDIR (created if missing), each PNG atomically (a temporary file renamed):
  trajectory.png      the pelvis path seen from above over the map (the level's boxes, drawn from level.toml: plotting
                      only), targets numbered, reached ones filled
  com_xyz.png         pelvis x, y and height over time
  target_distance.png distance to the current target over time, with target reached / stuck events, and the
                      obstacle factor below it
  gait_share.png      pie of each skill's share of the time
  statistics.png      the paper's statistics figure: the gait pie, a bar of targets reached and stuck recoveries, and
                      a histogram of the forward speed
  commands.png        vr and wr (the keys' command) over time
  phase_portrait.png  vr against wr, coloured by the target's bearing off the heading, with the keys' boundary
  gait_band.png       the skill in control as a colour band over time
  roll_pitch.png      pelvis roll and pitch over time
Needs matplotlib (Debian: python3-matplotlib, in scripts/setup.sh). Exit code 2 on bad input, with the reason.
"""
import csv
import math
import os
import sys
import tempfile

try:
    import tomllib
except ImportError:  # Python < 3.11
    tomllib = None

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Rectangle  # noqa: E402

SKILL_COLOURS = {"walk": "#2e7d32", "run": "#c62828", "stairs": "#1565c0", "stand": "#9e9e9e"}
NEEDED = ["t_s", "skill", "yaw_rad", "pelvis_x_m", "pelvis_y_m", "pelvis_z_m", "vel_x_m_per_s", "vel_y_m_per_s",
          "vr_m_per_s", "wr_rad_per_s", "target", "target_x_m", "target_y_m", "target_distance_m", "target_angle_rad",
          "obstacle_factor", "roll_rad", "pitch_rad", "events"]
# the commands the keys reach with the walk (tree.toml: W 1.2 m/s, A / D 1.0 rad/s, W with A or D 0.6 m/s at 0.5 rad/s;
# vx ramps 0.02 m/s and wz 0.03 rad/s a tick): from W, pressing A brings wz to 0.5 in 17 ticks while vx falls to 0.86;
# letting W go under A brings wz to 1.0 in 17 ticks while vx falls from 0.6 to 0.26. Their outline is the keys'
# speed-turn interlock boundary (wr, vr)
KEYS_BOUNDARY = [(-1.0, 0.0), (-1.0, 0.26), (-0.5, 0.86), (0.0, 1.2), (0.5, 0.86), (1.0, 0.26), (1.0, 0.0)]


def fail(message):
    print("garden_figures: " + message, file=sys.stderr)
    sys.exit(2)


def read_log(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{path}: {e.strerror}")
    if not rows:
        fail(f"{path}: no rows (a garden run's --log file has a header and 50 rows a second)")
    missing = [c for c in NEEDED if c not in rows[0]]
    if missing:
        fail(f"{path}:1: not a garden log: the columns {', '.join(missing)} are missing "
             "(play levels/garden --autopilot --log FILE writes them)")
    data = {c: [] for c in NEEDED}
    for i, r in enumerate(rows, start=2):
        for c in NEEDED:
            v = r[c]
            if c in ("skill", "events"):
                data[c].append(v or "")
            elif c == "target":
                try:
                    data[c].append(int(v))
                except ValueError:
                    fail(f"{path}:{i}: '{c}' = '{v}' is not a whole number")
            else:
                try:
                    data[c].append(float(v))
                except ValueError:
                    fail(f"{path}:{i}: '{c}' = '{v}' is not a number")
    return data


def level_boxes(level):
    """(x0, y0, w, h, colour, height) of each box and stair step, from the level file (for drawing only)."""
    if level is None or tomllib is None:
        return []
    path = os.path.join(level, "level.toml") if os.path.isdir(level) else level
    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        print(f"garden_figures: {path}: {e}; the map is left out", file=sys.stderr)
        return []
    out = []
    for b in doc.get("box", []) + doc.get("wall", []):
        (cx, cy, cz), (sx, sy, sz) = b["centre"], b["size"]
        out.append((cx - sx / 2, cy - sy / 2, sx, sy, b.get("colour", "#9a7b5a"), sz))
    for s in doc.get("stairs", []):
        x, y = s["start"]
        steps, run, width = int(s["steps"]), float(s["run"]), float(s.get("width", 1.5))
        top = float(s.get("top", run))
        length = (steps - 1) * run + top + ((steps - 1) * run if s.get("down", False) else 0.0)
        for k in range(int(round(length / run)) + 1):
            x0 = x + k * run
            if x0 >= x + length - 1e-9:
                break
            out.append((x0, y - width / 2, min(run, x + length - x0), width, s.get("colour", "#c8b08a"), 0.0))
    return out


def save(fig, outdir, name):
    fd, tmp = tempfile.mkstemp(prefix="." + name, suffix=".png", dir=outdir)
    os.close(fd)
    fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    os.replace(tmp, os.path.join(outdir, name))
    return name


def event_times(d, word):
    return [t for t, e in zip(d["t_s"], d["events"]) if word in e.split("+")]


def figures(d, boxes, outdir):
    t = d["t_s"]
    written = []
    # trajectory over the map
    fig, ax = plt.subplots(figsize=(7, 7))
    for x0, y0, w, h, colour, _ in boxes:
        ax.add_patch(Rectangle((x0, y0), w, h, facecolor=colour, edgecolor="none", alpha=0.8))
    xs, ys = d["pelvis_x_m"], d["pelvis_y_m"]
    for i in range(1, len(xs)):
        ax.plot(xs[i - 1:i + 1], ys[i - 1:i + 1], color=SKILL_COLOURS.get(d["skill"][i], "#000000"), lw=1.5)
    reached = set()
    for i, e in enumerate(d["events"]):
        if "reached" in e.split("+") and i > 0:
            reached.add(d["target"][i - 1])
    seen = {}
    for k, tx, ty in zip(d["target"], d["target_x_m"], d["target_y_m"]):
        if k >= 0 and k not in seen and not math.isnan(tx):
            seen[k] = (tx, ty)
    for k, (tx, ty) in seen.items():
        ax.plot(tx, ty, "o", ms=8, mfc="#ffb300" if k in reached else "none", mec="#e65100")
        ax.annotate(str(k + 1), (tx, ty), textcoords="offset points", xytext=(5, 5), fontsize=8)
    ax.plot(xs[0], ys[0], "k^", ms=9)
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("trajectory (colour: skill; circles: targets, filled when reached)")
    written.append(save(fig, outdir, "trajectory.png"))

    fig, axes = plt.subplots(3, 1, figsize=(9, 6), sharex=True)
    for ax, key, label in zip(axes, ["pelvis_x_m", "pelvis_y_m", "pelvis_z_m"], ["x [m]", "y [m]", "CoM (pelvis) z [m]"]):
        ax.plot(t, d[key], lw=1)
        ax.set_ylabel(label)
    axes[-1].set_xlabel("time [s]")
    written.append(save(fig, outdir, "com_xyz.png"))

    fig, (ax, axf) = plt.subplots(2, 1, figsize=(9, 5), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.plot(t, d["target_distance_m"], lw=1)
    for x in event_times(d, "reached"):
        ax.axvline(x, color="#2e7d32", lw=0.8, alpha=0.7)
    for x in event_times(d, "stuck"):
        ax.axvline(x, color="#c62828", lw=1.2, ls="--")
    ax.set_ylabel("distance to target [m]")
    ax.set_title("target distance (green: target reached, red dashed: stuck)")
    axf.plot(t, d["obstacle_factor"], lw=1, color="#ef6c00")
    axf.set_ylim(-0.05, 1.05)
    axf.set_ylabel("obstacle factor")
    axf.set_xlabel("time [s]")
    written.append(save(fig, outdir, "target_distance.png"))

    counts = {}
    for s in d["skill"]:
        counts[s] = counts.get(s, 0) + 1
    fig, ax = plt.subplots(figsize=(5, 5))
    names = sorted(counts, key=lambda s: -counts[s])
    ax.pie([counts[s] for s in names], labels=names, autopct="%.1f%%",
           colors=[SKILL_COLOURS.get(s, "#777777") for s in names])
    ax.set_title("gait share of the time")
    written.append(save(fig, outdir, "gait_share.png"))

    # the paper's statistics figure: gait share, targets and stuck recoveries, forward speed
    fig, (a1, a2, a3) = plt.subplots(1, 3, figsize=(13, 4))
    a1.pie([counts[s] for s in names], labels=names, autopct="%.1f%%",
           colors=[SKILL_COLOURS.get(s, "#777777") for s in names])
    a1.set_title("gait share")
    reached_n, stuck_n = len(event_times(d, "reached")), len(event_times(d, "stuck"))
    bars = a2.bar(["targets reached", "stuck recoveries"], [reached_n, stuck_n], color=["#2e7d32", "#c62828"])
    for b, v in zip(bars, [reached_n, stuck_n]):
        a2.annotate(str(v), (b.get_x() + b.get_width() / 2, v), ha="center", va="bottom")
    a2.set_title("navigation")
    forward = [vx * math.cos(y) + vy * math.sin(y)
               for vx, vy, y in zip(d["vel_x_m_per_s"], d["vel_y_m_per_s"], d["yaw_rad"])]
    a3.hist(forward, bins=40, color="#1565c0")
    a3.set_xlabel("forward speed [m/s]")
    a3.set_ylabel("samples (50 Hz)")
    a3.set_title("forward speed")
    fig.tight_layout()
    written.append(save(fig, outdir, "statistics.png"))

    fig, axes = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
    axes[0].plot(t, d["vr_m_per_s"], lw=1)
    axes[0].set_ylabel("vr [m/s]")
    axes[1].plot(t, d["wr_rad_per_s"], lw=1, color="#6a1b9a")
    axes[1].set_ylabel("wr [rad/s]")
    axes[1].set_xlabel("time [s]")
    written.append(save(fig, outdir, "commands.png"))

    fig, ax = plt.subplots(figsize=(6, 5))
    angle = [abs(math.degrees(a)) if not math.isnan(a) else 0.0 for a in d["target_angle_rad"]]
    sc = ax.scatter(d["wr_rad_per_s"], d["vr_m_per_s"], s=3, alpha=0.5, c=angle, cmap="coolwarm", vmin=0, vmax=120)
    fig.colorbar(sc, ax=ax, label="|target angle| [deg]")
    ax.plot([p[0] for p in KEYS_BOUNDARY], [p[1] for p in KEYS_BOUNDARY], "--", color="#555555", lw=1,
            label="the keys' interlock boundary (walk)")
    ax.legend(loc="lower center", fontsize=8)
    ax.set_xlabel("wr [rad/s]")
    ax.set_ylabel("vr [m/s]")
    ax.set_title("vr-wr phase portrait")
    written.append(save(fig, outdir, "phase_portrait.png"))

    fig, ax = plt.subplots(figsize=(9, 1.6))
    start = 0
    for i in range(1, len(t) + 1):
        if i == len(t) or d["skill"][i] != d["skill"][start]:
            end = t[i] if i < len(t) else t[-1]
            ax.axvspan(t[start], end, color=SKILL_COLOURS.get(d["skill"][start], "#777777"), lw=0)
            start = i
    ax.set_yticks([])
    ax.set_xlim(t[0], t[-1])
    ax.set_xlabel("time [s]")
    ax.set_title("gait mode: " + ", ".join(f"{s} ({SKILL_COLOURS.get(s, 'grey')})" for s in names), fontsize=8)
    fig.tight_layout()
    written.append(save(fig, outdir, "gait_band.png"))

    fig, ax = plt.subplots(figsize=(9, 4))
    ax.plot(t, [math.degrees(r) for r in d["roll_rad"]], lw=1, label="roll")
    ax.plot(t, [math.degrees(p) for p in d["pitch_rad"]], lw=1, label="pitch")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("[deg]")
    ax.legend()
    written.append(save(fig, outdir, "roll_pitch.png"))
    return written


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    level = "levels/garden"
    if "--level" in argv:
        i = argv.index("--level")
        if i + 1 >= len(argv):
            fail("--level needs a level folder or file")
        level = argv[i + 1]
        args = [a for a in args if a != level]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    log, outdir = args
    data = read_log(log)
    os.makedirs(outdir, exist_ok=True)
    for name in figures(data, level_boxes(level if os.path.exists(level) else None), outdir):
        print(os.path.join(outdir, name))


if __name__ == "__main__":
    main(sys.argv[1:])
