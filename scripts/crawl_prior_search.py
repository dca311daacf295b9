#!/usr/bin/env python3
"""crawl_prior_search.py — tune the crawl's key-pose prior with an evolution strategy, scored in physics.

How the crawl's prior was found (docs/skills/crawl.md). The gait is described by 20 numbers (below):
the hands-and-knees pose, the swing of the shoulders and hips, the tuck of one side at a time, the cycle's period,
and the gains of the prior's `turn` (the joint offsets per rad/s of the yaw-rate command that the card's steering
and play's steering turn it with). Each candidate is written into a copy of the skill tree, and scored by the crawl
card with the prior alone (`treelearn --tree COPY eval crawl --prior-only`), 20 episodes per candidate, every
candidate of a generation on the same seed (100 + generation). The strategy is a separable CMA-ES with weighted
recombination (lambda 10, mu 5); the mean is evaluated too, for the record. Every evaluation goes to OUT/search.csv
and the state to OUT/state.json (the search resumes from it).

Score: passed share + 0.5 x mean progress / 5 m - 0.5 x share of falls during the crawl.

Usage: scripts/crawl_prior_search.py --bin build/treelearn --out runs/crawl_search [--generations 17] [--sigma 0.5]
       [--seed 11] [--start "x1 ... x20"]   (two evaluations at a time; about 90 s a generation on two cores)
       scripts/crawl_prior_search.py --write-tree DIR --start "x1 ... x20"   (only the tree copy of one vector)
"""
import argparse
import json
import math
import os
import random
import re
import shutil
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
SKILLS = os.path.join(HERE, '..', 'assets', 'skills')

NAMES = ['S', 'E', 'H', 'K', 'A',  # the pose on hands and knees: shoulder pitch, elbow, hip pitch, knee, ankle pitch
         'a_s', 'a_h',             # swing: shoulders +-a_s, hips -+a_h (a hand and the other side's knee forward)
         'e_t', 'h_t', 'k_t',      # the tuck of one side at mid-swing: elbow, hip pitch, knee
         'r_t', 'sr0', 'hr0',      # hip roll of the tucked side (out > 0), shoulder roll and hip roll of the pose (out > 0)
         'c_t', 'w_a', 'at',       # the tucked side's shoulder at mid-swing, waist twist with the swing, ankle tuck
         'T',                      # the cycle [s], to 0.04 s
         'tw', 'ts', 'th']         # turn: waist yaw, shoulder roll, hip yaw [rad per rad/s of wz], each within +-1
# where the search's second stage started (its first stage had started from an earlier hand-found gait:
# -1.72 -0.69 -1.63 2.14 0.13 0.40 0.20 0.30 -0.40 0.40 0 0 0 0 0 0 1.0, with the waist alone turning)
START = [-1.7323, -0.7262, -1.6651, 2.1556, 0.1218, 0.3499, 0.1581, 0.3224, -0.4400, 0.4231, -0.0161, -0.0034,
         -0.0116, 0.0047, -0.0045, 0.0496, 0.9509, 0.33, 0.0, 0.0]
# one step of the search in each number at sigma 1 [rad, s, rad per rad/s]
SCALE = [0.024, 0.024, 0.024, 0.03, 0.024, 0.024, 0.018, 0.024, 0.024, 0.03, 0.015, 0.018, 0.012, 0.024, 0.009,
         0.024, 0.024, 0.3, 0.3, 0.3]
LEAD_IN = '  { t = 0.34, offset = { hip_pitch = 0.560, knee = -0.120, ankle_pitch = 0.370, shoulder_pitch = -1.760, elbow = -0.560 } },'


def prior_text(x):
    p = dict(zip(NAMES, x))
    period = round(max(0.6, min(1.6, p['T'])) / 0.04) * 0.04
    clip = lambda v: max(-1.0, min(1.0, v))

    def side(left, sh=0.0, el=0.0, hp=0.0, kn=0.0, an=0.0, hr=0.0):
        out = 1.0 if left else -1.0  # roll joints: out is + on the left, - on the right
        return [p['S'] + sh, p['E'] + el, p['H'] + hp, p['K'] + kn, p['A'] + an, out * (p['hr0'] + hr), out * p['sr0']]

    def key(left, right, waist=0.0):
        d = {}
        for i, j in enumerate(['shoulder_pitch', 'elbow', 'hip_pitch', 'knee', 'ankle_pitch', 'hip_roll', 'shoulder_roll']):
            d['left_' + j], d['right_' + j] = left[i], right[i]
        if waist:
            d['waist_yaw'] = waist
        return '{ ' + ', '.join('%s = %.3f' % kv for kv in d.items()) + ' }'

    tuck = dict(sh=p['c_t'], el=p['e_t'], hp=p['h_t'], kn=p['k_t'], an=p['at'], hr=p['r_t'])
    k0 = key(side(True, sh=p['a_s'], hp=-p['a_h']), side(False, sh=-p['a_s'], hp=p['a_h']), p['w_a'])
    k1 = key(side(True, **tuck), side(False))
    k2 = key(side(True, sh=-p['a_s'], hp=p['a_h']), side(False, sh=p['a_s'], hp=-p['a_h']), -p['w_a'])
    k3 = key(side(True), side(False, **tuck))
    lines = [LEAD_IN, '  { t = 1.12, offset = %s },' % key(side(True), side(False))]
    for i, k in enumerate([k0, k1, k2, k3, k0]):
        lines.append('  { t = %.2f, offset = %s },' % (1.5 + i * period / 4, k))
    turn = 'turn = { waist_yaw = %.3f, shoulder_roll = %.3f, hip_yaw = %.3f }' % (clip(p['tw']), clip(p['ts']), clip(p['th']))
    return 'prior = { type = "keyframes", repeat_from = 1.5, %s, keys = [\n%s\n] }\n' % (turn, '\n'.join(lines))


def write_tree(x, folder):
    """A copy of the shipped tree with the crawl's prior replaced, the models linked beside it."""
    os.makedirs(folder, exist_ok=True)
    for f in os.listdir(SKILLS):
        if f != 'tree.toml' and not os.path.lexists(os.path.join(folder, f)):
            os.symlink(os.path.abspath(os.path.join(SKILLS, f)), os.path.join(folder, f))
    text = open(os.path.join(SKILLS, 'tree.toml')).read()
    section = text.find('[skill.crawl]\n') if '[skill.crawl]\n' in text else text.find('[skill.crawl] ')
    begin = text.find('\nprior = { type = "keyframes"', section) + 1
    end = text.find('\n] }\n', begin) + 5
    if section < 0 or begin <= 0 or end < 5 or text.find('\n[skill.', section + 1) < begin:
        sys.exit('crawl_prior_search: no keyframes prior found in [skill.crawl] of assets/skills/tree.toml')
    text = text[:begin] + prior_text(x) + text[end:]
    tmp = os.path.join(folder, 'tree.toml.tmp')
    open(tmp, 'w').write(text)
    os.replace(tmp, os.path.join(folder, 'tree.toml'))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--bin', default=os.path.join(HERE, '..', 'build', 'treelearn'))
    ap.add_argument('--out', default='runs/crawl_search')
    ap.add_argument('--generations', type=int, default=17)
    ap.add_argument('--sigma', type=float, default=0.5)
    ap.add_argument('--seed', type=int, default=11)
    ap.add_argument('--episodes', type=int, default=20)
    ap.add_argument('--start', help='20 numbers (NAMES), default START')
    ap.add_argument('--write-tree', metavar='DIR', help='only write the tree copy of --start into DIR')
    a = ap.parse_args()
    start = [float(v) for v in a.start.split()] if a.start else START
    if len(start) != len(NAMES):
        sys.exit('crawl_prior_search: --start needs %d numbers (%s), got %d' % (len(NAMES), ' '.join(NAMES), len(start)))
    if a.write_tree:
        write_tree(start, a.write_tree)
        return
    if not os.access(a.bin, os.X_OK):
        sys.exit('crawl_prior_search: %s is not an executable (build first: scripts/setup.sh)' % a.bin)
    os.makedirs(a.out, exist_ok=True)
    dim, lam, mu = len(NAMES), 10, 5
    w = [math.log(mu + 0.5) - math.log(i + 1) for i in range(mu)]
    w = [v / sum(w) for v in w]
    mueff = 1 / sum(v * v for v in w)
    cs = (mueff + 2) / (dim + mueff + 5)
    ds = 1 + 2 * max(0, math.sqrt((mueff - 1) / (dim + 1)) - 1) + cs
    cc = 4 / (dim + 4)
    c1 = 2 / ((dim + 1.3) ** 2 + mueff) * (dim + 2) / 3
    cmu = min(1 - c1, 2 * (mueff - 2 + 1 / mueff) / ((dim + 2) ** 2 + mueff) * (dim + 2) / 3)
    chi = math.sqrt(dim) * (1 - 1 / (4 * dim) + 1 / (21 * dim * dim))
    state = {'mean': [0.0] * dim, 'sigma': a.sigma, 'C': [1.0] * dim, 'ps': [0.0] * dim, 'pc': [0.0] * dim, 'g': -1}
    state_file = os.path.join(a.out, 'state.json')
    if os.path.exists(state_file):
        state = json.load(open(state_file))
        print('resuming after generation %d' % state['g'])
    rng = random.Random(a.seed * 1000 + state['g'] + 1)
    log = open(os.path.join(a.out, 'search.csv'), 'a')
    for g in range(state['g'] + 1, a.generations):
        m, sigma, C = state['mean'], state['sigma'], state['C']
        zs = [[rng.gauss(0, 1) for _ in range(dim)] for _ in range(lam)]
        ys = [[math.sqrt(C[i]) * z[i] for i in range(dim)] for z in zs]
        steps = [[m[i] + sigma * y[i] for i in range(dim)] for y in ys] + [m]
        xs = [[start[i] + SCALE[i] * s[i] for i in range(dim)] for s in steps]
        results, running, todo = [None] * len(xs), {}, list(range(len(xs)))
        while todo or running:  # two cards at a time, one thread each
            while todo and len(running) < 2:
                k = todo.pop(0)
                folder = os.path.join(a.out, 'trees', str(k))
                write_tree(xs[k], folder)
                running[k] = subprocess.Popen([a.bin, '--tree', os.path.join(folder, 'tree.toml'), 'eval', 'crawl',
                                               '--prior-only', '--seed', str(100 + g), '--episodes', str(a.episodes),
                                               '--threads', '1'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            time.sleep(0.2)
            for k, proc in list(running.items()):
                if proc.poll() is None:
                    continue
                out = proc.stdout.read()
                del running[k]
                passed = re.search(r'no fall\s+([\d.]+)', out)
                if not passed:
                    sys.exit('crawl_prior_search: the crawl card printed no result:\n' + out[-2000:])
                prog = float(re.search(r'mean progress along the tunnel \[m\]\s+([\d.-]+)', out).group(1))
                f = re.search(r"during crawl (\d+); out of the tunnel's side (\d+)", out)
                results[k] = (float(passed.group(1)), prog, int(f.group(1)), int(f.group(2)))
        score = [r[0] / 100 + 0.5 * min(r[1], 5) / 5 - 0.5 * r[2] / a.episodes for r in results]
        for k, (x, r, s) in enumerate(zip(xs, results, score)):
            log.write('%d,%d,%d,%.4f,%.1f,%.3f,%d,%d,%s\n' % (g, k, 100 + g, s, r[0], r[1], r[2], r[3], ' '.join('%.4f' % v for v in x)))
        log.flush()
        order = sorted(range(lam), key=lambda k: -score[k])
        yw = [sum(w[j] * ys[order[j]][i] for j in range(mu)) for i in range(dim)]
        zw = [sum(w[j] * zs[order[j]][i] for j in range(mu)) for i in range(dim)]
        m = [m[i] + sigma * yw[i] for i in range(dim)]
        ps = [(1 - cs) * state['ps'][i] + math.sqrt(cs * (2 - cs) * mueff) * zw[i] for i in range(dim)]
        nps = math.sqrt(sum(v * v for v in ps))
        hs = nps / math.sqrt(1 - (1 - cs) ** (2 * (g + 1))) < (1.4 + 2 / (dim + 1)) * chi
        pc = [(1 - cc) * state['pc'][i] + (math.sqrt(cc * (2 - cc) * mueff) * yw[i] if hs else 0) for i in range(dim)]
        C = [(1 - c1 - cmu) * C[i] + c1 * pc[i] ** 2 + cmu * sum(w[j] * ys[order[j]][i] ** 2 for j in range(mu)) for i in range(dim)]
        sigma = min(2.0, sigma * math.exp((cs / ds) * (nps / chi - 1)))
        state = {'mean': m, 'sigma': sigma, 'C': C, 'ps': ps, 'pc': pc, 'g': g}
        tmp = state_file + '.tmp'
        json.dump(state, open(tmp, 'w'))
        os.replace(tmp, state_file)
        mean_x = ' '.join('%.4f' % (start[i] + SCALE[i] * m[i]) for i in range(dim))
        print('generation %d (seed %d): best %.0f %%, the mean %.0f %%; sigma %.3f; new mean: %s' % (
            g, 100 + g, results[order[0]][0], results[-1][0], sigma, mean_x), flush=True)
        shutil.rmtree(os.path.join(a.out, 'trees'), ignore_errors=True)


if __name__ == '__main__':
    main()
