#!/usr/bin/python3
"""compare_figures.py — the comparison's figures from `treelearn experiment compare --out OUT` (docs/comparison.md).

Usage: python3 scripts/compare_figures.py OUT [FIGDIR]   (FIGDIR defaults to OUT/figures)

Writes, with matplotlib (Debian python3-matplotlib):
  reward_SKILL.png  the mean episode return in training against the skill's own environment steps, one line per arm
                    and seed (the tree arm's from OUT/tree/seedK/SKILL/log.csv, the multi-task arms' from their
                    skills.csv, at a sixth of the network's steps: each skill's share), the paper's Figs. 4-9;
  radar.png         each arm's final mean episode return per skill from OUT/results.csv (the rewards measure:
                    deterministic actions in the skill's own training episodes), each skill scaled by its largest
                    value over the arms, the paper's Fig. 10;
  cards.png         the share of each arm's final policies whose report card passes, per skill;
  forgetting.png,   after each stage of the paper's order, the card score of every skill learnt so far: on the
  retention.png     sequential arm's one network, and on the tree's own models (OUT/matrices.csv, seed 1).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

SKILLS = ["walk", "run", "squat", "jump", "crawl", "one_leg"]
ARMS = ["tree", "sequential", "multitask1x", "multitask6x", "multitaskwalk"]
COLOURS = {"tree": "tab:green", "sequential": "tab:purple", "multitask1x": "tab:red", "multitask6x": "tab:orange",
           "multitaskwalk": "tab:blue"}
LABELS = {"tree": "tree (from the parent's weights)", "sequential": "one network, the skills in turn",
          "multitask1x": "multi-task, 10^7 in all", "multitask6x": "multi-task, 6 x 10^7 in all",
          "multitaskwalk": "multi-task from the walk, 10^7 in all"}


def number(text):
    try:
        v = float(text)
    except ValueError:
        return math.nan
    return v


def seeds(folder):
    if not os.path.isdir(folder):
        return []
    return sorted(d for d in os.listdir(folder) if d.startswith("seed"))


def tree_curve(out, seed, skill, arm="tree"):
    path = os.path.join(out, "tree", seed, skill, "log.csv")
    if arm == "sequential" and skill != SKILLS[0]:
        path = os.path.join(out, "sequential", seed, f"{SKILLS.index(skill) + 1}_{skill}", "log.csv")
    if not os.path.exists(path):
        return [], []
    xs, ys = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            xs.append(number(row["env_steps"]))
            ys.append(number(row["mean_episode_return"]))
    return xs, ys


def multitask_curve(out, arm, seed, skill):
    path = os.path.join(out, arm, seed, "skills.csv")
    if not os.path.exists(path):
        return [], []
    xs, ys = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            if row["skill"] == skill:
                xs.append(number(row["env_steps"]) / len(SKILLS))
                ys.append(number(row["mean_episode_return"]))
    return xs, ys


def main():
    if len(sys.argv) not in (2, 3):
        sys.exit(__doc__)
    out = sys.argv[1]
    figdir = sys.argv[2] if len(sys.argv) == 3 else os.path.join(out, "figures")
    results_path = os.path.join(out, "results.csv")
    if not os.path.exists(results_path):
        sys.exit(f"{results_path}: no results yet (run treelearn experiment compare --out {out} first)")
    os.makedirs(figdir, exist_ok=True)

    for skill in SKILLS:
        fig, ax = plt.subplots(figsize=(7, 4))
        for arm in ARMS:
            folder = os.path.join(out, arm)
            for i, seed in enumerate(seeds(folder)):
                if arm in ("tree", "sequential"):
                    xs, ys = tree_curve(out, seed, skill, arm)
                else:
                    xs, ys = multitask_curve(out, arm, seed, skill)
                if xs:
                    ax.plot(xs, ys, color=COLOURS[arm], alpha=0.9 if i == 0 else 0.5,
                            label=LABELS[arm] if i == 0 else None)
        ax.set_title(f"{skill}: mean episode return in training")
        ax.set_xlabel("the skill's environment steps")
        ax.set_ylabel("episode return")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(os.path.join(figdir, f"reward_{skill}.png"), dpi=100)
        plt.close(fig)

    # final returns (mean over seeds) and card passes per arm and skill
    final = {arm: {s: [] for s in SKILLS} for arm in ARMS}
    passed = {arm: {s: [] for s in SKILLS} for arm in ARMS}
    with open(results_path) as f:
        for row in csv.DictReader(f):
            if row["arm"] in final and row["skill"] in SKILLS:
                final[row["arm"]][row["skill"]].append(number(row["mean_episode_return"]))
                passed[row["arm"]][row["skill"]].append(row["card_pass"] == "1")

    def mean(values):
        values = [v for v in values if not math.isnan(v)]
        return sum(values) / len(values) if values else math.nan

    top = {s: max([mean(final[a][s]) for a in ARMS if not math.isnan(mean(final[a][s]))] or [1.0]) for s in SKILLS}
    angles = [2 * math.pi * k / len(SKILLS) for k in range(len(SKILLS))] + [0.0]
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(111, polar=True)
    for arm in ARMS:
        values = [mean(final[arm][s]) / top[s] if top[s] > 0 else math.nan for s in SKILLS]
        if all(math.isnan(v) for v in values):
            continue
        values = [0.0 if math.isnan(v) else max(0.0, v) for v in values]
        ax.plot(angles, values + values[:1], color=COLOURS[arm], label=LABELS[arm])
        ax.fill(angles, values + values[:1], color=COLOURS[arm], alpha=0.1)
    ax.set_xticks(angles[:-1])
    ax.set_xticklabels([f"{s}\n({top[s]:.0f})" for s in SKILLS])
    ax.set_ylim(0, 1.05)
    ax.set_title("final mean episode return, each skill over its best arm (in brackets)", fontsize=10)
    ax.legend(loc="lower left", bbox_to_anchor=(-0.1, -0.15), fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "radar.png"), dpi=100)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 3.5))
    width = 0.8 / len(ARMS)
    for i, arm in enumerate(ARMS):
        shares = [100 * mean([1.0 if p else 0.0 for p in passed[arm][s]]) for s in SKILLS]
        ax.bar([k + (i - (len(ARMS) - 1) / 2) * width for k in range(len(SKILLS))], [0 if math.isnan(v) else v for v in shares],
               width=width, color=COLOURS[arm], label=LABELS[arm])
    ax.set_xticks(range(len(SKILLS)))
    ax.set_xticklabels(SKILLS)
    ax.set_ylabel("cards passed [%]")
    ax.set_ylim(0, 105)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(figdir, "cards.png"), dpi=100)
    plt.close(fig)
    matrices_path = os.path.join(out, "matrices.csv")
    cells = {}
    if os.path.exists(matrices_path):
        with open(matrices_path) as f:
            for row in csv.DictReader(f):
                if row["seed"] == "1":
                    cells[(row["arm"], int(row["stage"]), row["skill"])] = (number(row["card_score"]),
                                                                           row["card_pass"] == "1")
    for arm, name, title in (("sequential", "forgetting", "one network, the skills in turn: forgetting"),
                             ("tree", "retention", "the tree's own models: retention")):
        fig, ax = plt.subplots(figsize=(6.5, 5))
        grid = [[math.nan] * len(SKILLS) for _ in SKILLS]
        for k in range(len(SKILLS)):
            for j in range(k + 1):
                if (arm, k + 1, SKILLS[j]) in cells:
                    grid[k][j] = cells[(arm, k + 1, SKILLS[j])][0]
        image = ax.imshow(grid, cmap="viridis")
        for k in range(len(SKILLS)):
            for j in range(k + 1):
                if (arm, k + 1, SKILLS[j]) in cells:
                    score, ok = cells[(arm, k + 1, SKILLS[j])]
                    ax.text(j, k, f"{score:.2f}\n{'pass' if ok else 'fail'}", ha="center", va="center", fontsize=7,
                            color="white")
        ax.set_xticks(range(len(SKILLS)))
        ax.set_xticklabels(SKILLS)
        ax.set_yticks(range(len(SKILLS)))
        ax.set_yticklabels([f"after {k + 1}: {s}" for k, s in enumerate(SKILLS)])
        ax.set_xlabel("card of")
        ax.set_title(title + " (card score)", fontsize=10)
        fig.colorbar(image, ax=ax, shrink=0.8)
        fig.tight_layout()
        fig.savefig(os.path.join(figdir, f"{name}.png"), dpi=100)
        plt.close(fig)

    print(f"figures in {figdir}: reward_SKILL.png for {', '.join(SKILLS)}, radar.png, cards.png, forgetting.png, retention.png")


if __name__ == "__main__":
    main()
