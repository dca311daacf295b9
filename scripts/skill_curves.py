#!/usr/bin/python3
"""Draw the training curve of every shipped skill: docs/skills/SKILL.png from the logs in docs/skills/.

A shipped model is often the end of several training stages (a branch from its parent, then fine-tunes, each from
the policy the stage before exported). Each stage gets one panel, in order: the mean reward per tick against that
stage's env steps (left axis) and, where the run logged one, the training card's score (right axis, dots). A dashed
line marks the policy the stage handed on (the next stage's start, or the shipped model).

Usage: scripts/skill_curves.py [SKILL ...]     (default: all eleven; run from anywhere)
Needs python3-matplotlib (Debian). The logs are every 10th PPO iteration of a run's log.csv plus every evaluation.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
DOCS = os.path.join(ROOT, "docs", "skills")

# skill -> stages in training order: (log file in docs/skills, label, env steps of the policy the stage handed on;
# None = the stage's last policy)
STAGES = {
    "walk": [
        ("walk.train.csv", "from scratch", 9_420_800),
        ("walk.finetune.train.csv", "steps in place at zero command", 6_144_000),
        ("walk.push.train.csv", "harder training pushes", None),
        ("walk.hold.train.csv", "hold_position", 1_024_000),
    ],
    "run": [
        ("run.train.csv", "from walk, 6-lesson curriculum", 17_612_800),
        ("run.heading1.train.csv", "heading_hold 1.0", None),
        ("run.heading.train.csv", "heading_hold 2.0", 2_949_120),
        ("run.steer2.train.csv", "steering draws, vx to 2.2", 3_276_800),
    ],
    "stairs": [
        ("stairs.train.csv", "from walk: sight, straight draws", None),
        ("stairs.se5.train.csv", "orientation 0.4; 4 steps", None),
        ("stairs.sb1.train.csv", "spawn_along 0.5", 5_632_000),
        ("stairs.sc1.train.csv", "spawn_along 0.8", None),
        ("stairs.st1.train.csv", "log-std -1.8, live 2", 11_878_400),
        ("stairs.lb1.train.csv", "step_look_back, steered", 5_120_000),
        ("stairs.r1.train.csv", "turn draws again", 2_867_200),
        ("stairs.mx1.train.csv", "half the episodes steered", 1_024_000),
        ("stairs.play.train.csv", "40 % from play's handovers", None),
        ("stairs.range.train.csv", "staircases drawn, 20 deg starts", 2_969_600),
    ],
    "squat": [
        ("squat.train.csv", "from walk", 3_276_800),
        ("squat.handover.train.csv", "handovers from walk", None),
    ],
    "jump": [
        ("jump.train.csv", "from squat, one jump per episode", 491_520),
        ("jump.jt26.train.csv", "6 s episodes, log-std -1.8", 8_028_160),
        ("jump.play.train.csv", "40 % from play's handovers", 3_686_400),
    ],
    "one_leg": [
        ("one_leg.train.csv", "from walk, filter 0.5", 2_662_400),
        ("one_leg.handover.train.csv", "handovers from walk", None),
    ],
    "kick": [
        ("kick.train.csv", "from one_leg, from the spawn", 11_468_800),
        ("kick.handover.train.csv", "entered as play enters it", 3_932_160),
    ],
    "prone": [
        ("prone.train.csv", "from walk", 3_276_800),
        ("prone.handover.train.csv", "handovers from current walk", None),
    ],
    "pushup": [("pushup.train.csv", "from prone (prior alone)", 409_600)],
    "crawl": [("crawl.train.csv", "from prone (tuned prior)", 409_600)],
    "standup": [("standup.train.csv", "from prone (prior alone)", 5_324_800)],
}


def read_log(path):
    """Rows of a training log as (env steps, mean reward, card score or None), in file order."""
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            score = r.get("eval_score", "")
            rows.append((int(float(r["env_steps"])), float(r["mean_reward"]),
                         float(score) if score not in ("", "nan") else None))
    return rows


def draw(skill):
    stages = STAGES[skill]
    cols = min(4, len(stages))
    rows_n = (len(stages) + cols - 1) // cols
    fig, axes = plt.subplots(rows_n, cols, figsize=(max(4.5, 3.4 * cols), 3.0 * rows_n + 0.4), squeeze=False)
    panels = [ax for row in axes for ax in row]
    for ax in panels[len(stages):]:
        ax.axis("off")
    for ax, (log, label, handed_on) in zip(panels, stages):
        rows = read_log(os.path.join(DOCS, log))
        steps = [r[0] / 1e6 for r in rows]
        ax.plot(steps, [r[1] for r in rows], color="tab:blue", lw=1.2)
        ax.set_title(f"{log}\n{label}", fontsize=8)
        ax.set_xlabel("env steps [M]", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
        scored = [(r[0] / 1e6, r[2]) for r in rows if r[2] is not None]
        if scored:
            card = ax.twinx()
            card.plot([s[0] for s in scored], [s[1] for s in scored], "o", ms=2.5, color="tab:orange")
            card.tick_params(labelsize=7, colors="tab:orange")
        ax.axvline((handed_on if handed_on is not None else rows[-1][0]) / 1e6, color="k", ls="--", lw=0.8)
    for row in axes:
        row[0].set_ylabel("mean reward per tick", fontsize=8, color="tab:blue")
    fig.suptitle(f"{skill}: training stages in order (orange dots: training card score; dashed: policy kept)",
                 fontsize=9)
    fig.tight_layout()
    out = os.path.join(DOCS, f"{skill}.png")
    fig.savefig(out, dpi=90)
    plt.close(fig)
    return out


def main(argv):
    skills = argv[1:] or list(STAGES)
    for s in skills:
        if s not in STAGES:
            sys.exit(f"skill_curves.py: unknown skill '{s}' (known: {', '.join(STAGES)})")
        print(draw(s))


if __name__ == "__main__":
    main(sys.argv)
