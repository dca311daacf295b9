#!/usr/bin/python3
"""scaling_model.py — the modelled throughput of `mpirun -np N treelearn train` on a cluster (docs/scaling.md).

Usage: scripts/scaling_model.py LOG.csv OUTDIR

LOG.csv is a one-rank, one-thread training run's log (`treelearn train walk --threads 1 --eval-every 0 --steps 81920
--run-dir R` writes R/log.csv): its per-iteration physics, inference and update seconds (first iteration dropped) give
the cost of one sample on one core. The model adds, per iteration, what the ranks exchange (ai/dist/comm.h,
ai/ppo/trainer.cpp):
  - the gradient: 30 sums (10 minibatches x 3 epochs) of 609,455 floats (the 3x512 actor, the 2x128 critic, the
    log-std: 2.44 MB), bandwidth-optimal (2 (N-1)/N x bytes / bandwidth) plus 2 log2 N latencies;
  - 4 small sums per minibatch and a few per iteration (advantage statistics, losses): 2 log2 N latencies each;
  - the normaliser: every rollout step sums every rank's observation count, sums and squares about the running mean
    (173 doubles), 1,024 times an iteration; for comparison, the column steps_per_s_gathered gathers the observations
    themselves instead (86 floats per environment; (N-1)/N x bytes / bandwidth plus log2 N latencies), which would
    give every rank the exact batch one process sees.
Networks: 10 Gbit/s Ethernet (20 us latency) and 100 Gbit/s InfiniBand-class (3 us). A rank of k cores computes k
times as fast as one core (optimistic: two threads here give 1.84x). Two regimes:
  weak           every rank keeps 10 environments x 1,024 steps (the run's buffer and minibatches grow with N);
  weak-per-core  10 environments per core of the rank (a larger batch per rank);
  strong         the run's buffer stays 20,480 samples of 20 environments (N <= 20).
Writes OUTDIR/scaling.csv and OUTDIR/scaling.png, each atomically. Needs matplotlib (Debian: python3-matplotlib).
Exit code 2 on bad input, with the reason.
"""
import csv
import math
import os
import sys
import tempfile

PARAMETERS = 609455  # actor 86-512-512-512-23, critic 86-128-128-1, log-std 23
OBS_FLOATS = 86
STEPS_PER_ENV = 1024
ALLREDUCES = 30  # gradient sums per iteration
SMALL_SUMS = 4 * 30 + 8
NETWORKS = {"10 Gbit/s": (10e9 / 8, 20e-6), "100 Gbit/s": (100e9 / 8, 3e-6)}
CORES = [1, 8, 32]
RANKS = [1, 2, 4, 8, 16, 20, 32, 64, 128, 256]


def fail(message):
    print(f"scaling_model: {message}", file=sys.stderr)
    sys.exit(2)


def per_sample_seconds(log_path):
    try:
        with open(log_path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        fail(f"{log_path}: {e.strerror}")
    for column in ("rollout_physics_s", "inference_s", "update_s", "env_steps"):
        if not rows or column not in rows[0]:
            fail(f"{log_path}: no '{column}' column (a treelearn train log.csv?)")
    if len(rows) < 2:
        fail(f"{log_path}: needs at least two iterations (the first is dropped)")
    rows = rows[1:]
    samples = int(rows[0]["env_steps"]) // (int(rows[0]["iteration"]))
    mean = lambda c: sum(float(r[c]) for r in rows) / len(rows)
    return {c: mean(c) / samples for c in ("rollout_physics_s", "inference_s", "update_s")}, samples


def allreduce(nbytes, ranks, bandwidth, latency):
    if ranks == 1:
        return 0.0
    return 2 * (ranks - 1) / ranks * nbytes / bandwidth + 2 * math.log2(ranks) * latency


def allgather(total_bytes, ranks, bandwidth, latency):
    if ranks == 1:
        return 0.0
    return (ranks - 1) / ranks * total_bytes / bandwidth + math.ceil(math.log2(ranks)) * latency


def iteration(ranks, envs_per_rank, cost, cores, network):
    """steps/s, and an iteration's compute, gradient, small-sum and observation-gather seconds"""
    bandwidth, latency = NETWORKS[network]
    samples = envs_per_rank * STEPS_PER_ENV
    compute = samples * cost / cores
    gradient = ALLREDUCES * allreduce(4 * PARAMETERS, ranks, bandwidth, latency)
    small = SMALL_SUMS * allreduce(8, ranks, bandwidth, latency)
    moments = STEPS_PER_ENV * allreduce(8 * (2 * OBS_FLOATS + 1), ranks, bandwidth, latency)
    # the alternative: gather the observations themselves
    gather = STEPS_PER_ENV * allgather(4 * OBS_FLOATS * envs_per_rank * ranks, ranks, bandwidth, latency)
    rest = compute + gradient + small
    return ranks * samples / (rest + moments), compute, gradient, small, moments, ranks * samples / (rest + gather)


def write_atomic(path, write):
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-")
    os.close(fd)
    try:
        write(tmp)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def main():
    if len(sys.argv) != 3:
        fail("usage: scripts/scaling_model.py LOG.csv OUTDIR")
    parts, samples = per_sample_seconds(sys.argv[1])
    cost = sum(parts.values())
    os.makedirs(sys.argv[2], exist_ok=True)
    rows = []
    for network in NETWORKS:
        for cores in CORES:
            for regime in ("weak", "weak-per-core", "strong"):
                for n in RANKS:
                    if regime == "strong" and (n > 20 or 20 % n):
                        continue
                    envs = {"weak": 10, "weak-per-core": 10 * cores, "strong": 20 // max(1, n)}[regime]
                    if regime == "weak-per-core" and cores == 1:
                        continue  # the same as weak
                    rate, compute, gradient, small, normaliser, gathered = iteration(n, envs, cost, cores, network)
                    ideal = n * cores / cost
                    rows.append({"network": network, "cores_per_rank": cores, "regime": regime, "ranks": n,
                                 "envs_per_rank": envs, "steps_per_s": round(rate),
                                 "efficiency": round(rate / ideal, 3), "compute_s": round(compute, 4),
                                 "gradient_s": round(gradient, 4), "small_sums_s": round(small, 4),
                                 "normaliser_s": round(normaliser, 4), "steps_per_s_gathered": round(gathered)})

    def write_csv(tmp):
        with open(tmp, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)

    write_atomic(os.path.join(sys.argv[2], "scaling.csv"), write_csv)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.4), sharey=True)
    for ax, network in zip(axes, NETWORKS):
        for cores, colour in zip(CORES, ("tab:blue", "tab:orange", "tab:green")):
            for regime, style, what in (("weak", "-", "10 envs/rank"), ("weak-per-core", "-.", "10 envs/core"),
                                        ("strong", "--", "20 envs in all")):
                pts = [(r["ranks"], r["steps_per_s"]) for r in rows
                       if r["network"] == network and r["cores_per_rank"] == cores and r["regime"] == regime]
                if pts:
                    ax.loglog(*zip(*pts), style, color=colour, marker="o", markersize=3,
                              label=f"{cores} core{'s' if cores > 1 else ''}/rank, {what}")
            ideal = [n * cores / cost for n in RANKS]
            ax.loglog(RANKS, ideal, ":", color=colour, linewidth=0.8)
        ax.set_title(f"{network} (dotted: linear)")
        ax.set_xlabel("ranks")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("environment steps per second")
    axes[0].legend(fontsize=7)
    fig.suptitle(f"PPO over MPI ranks, modelled from {cost * 1e6:.0f} us per sample on one core "
                 f"(physics {parts['rollout_physics_s'] * 1e6:.0f}, inference {parts['inference_s'] * 1e6:.0f}, "
                 f"update {parts['update_s'] * 1e6:.0f})", fontsize=10)
    fig.tight_layout()
    write_atomic(os.path.join(sys.argv[2], "scaling.png"), lambda tmp: fig.savefig(tmp, dpi=110, format="png"))
    print(f"one core: {cost * 1e6:.0f} us a sample ({1 / cost:.0f} steps/s)")
    print("network     cores/rank  envs/rank  ranks    steps/s  efficiency  an iteration: compute / gradient / "
          "small sums / normaliser [s]   steps/s, observations gathered")
    for r in rows:
        if r["ranks"] in (1, 8, 64, 256) and r["regime"] != "strong":
            print(f"{r['network']:>10}  {r['cores_per_rank']:10d}  {r['envs_per_rank']:9d}  {r['ranks']:5d}  "
                  f"{r['steps_per_s']:>10,}  {r['efficiency']:10.2f}  {r['compute_s']:.3f} / {r['gradient_s']:.3f} / "
                  f"{r['small_sums_s']:.3f} / {r['normaliser_s']:.3f}   {r['steps_per_s_gathered']:>10,}")


if __name__ == "__main__":
    main()
