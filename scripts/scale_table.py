#!/usr/bin/env python3
"""Markdown table of scripts/bench_scale.sh: per pipeline stage and frame
count, wall seconds, CPU seconds and peak memory (the stage's own record in
ws/pipeline/stages.json), and the growth exponent of wall time and of peak
memory between consecutive frame counts, log(y2 / y1) / log(n2 / n1): 1 is
linear, n log n from 200 to 600 frames is about 1.1. The last row is the
whole process: elapsed wall and user + system CPU of /usr/bin/time -v, and
the largest of the stages' peaks (not time's maximum resident set size: the
pipeline resets the kernel's high-water mark at every stage, which time's
figure follows, so it reports the last stage's). Sizes whose run has not
finished are left out.

A second table gives what each size reconstructs, from ws/eval: images
registered, mean camera position / rotation error after the sim3 of centres
and axes, mesh F at 0.05 / 0.1 m and precision at 0.5 m (ours; and
LIDAR-only Poisson beside), so that a bounded-memory change can show that
the mesh at 600 frames is as good as at 60.

Usage: scale_table.py --work DIR --frames 60,200,600
"""
import argparse
import json
import math
import os
import re
import sys


def read_time(path):
    """(wall s, cpu s, maximum resident set bytes) of a /usr/bin/time -v
    report."""
    text = open(path).read()
    wall = re.search(r'Elapsed \(wall clock\) time.*: (\S+)', text).group(1)
    seconds = 0.0
    for part in wall.split(':'):
        seconds = 60.0 * seconds + float(part)
    user = float(re.search(r'User time \(seconds\): (\S+)', text).group(1))
    system = float(re.search(r'System time \(seconds\): (\S+)', text).group(1))
    peak_kib = int(re.search(r'Maximum resident set size \(kbytes\): (\d+)', text).group(1))
    return seconds, user + system, peak_kib * 1024


def exponent(n1, y1, n2, y2):
    if y1 <= 0 or y2 <= 0:
        return '-'
    return '%.2f' % (math.log(y2 / y1) / math.log(n2 / n1))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--work', required=True)
    parser.add_argument('--frames', required=True)
    args = parser.parse_args()
    sizes, runs = [], {}
    for n in (int(x) for x in args.frames.split(',')):
        stages_path = os.path.join(args.work, str(n), 'ws', 'pipeline', 'stages.json')
        time_path = os.path.join(args.work, str(n), 'time.txt')
        if not (os.path.exists(os.path.join(args.work, str(n), 'done')) and
                os.path.exists(stages_path) and os.path.exists(time_path)):
            print(f'{n} frames: no finished run, left out', file=sys.stderr)
            continue
        stages = {}
        for record in json.load(open(stages_path))['stages']:
            stages[record['stage']] = (record['wall_seconds'], record['cpu_seconds'],
                                       record['peak_memory_bytes'])
        wall, cpu, _ = read_time(time_path)
        stages['whole process'] = (wall, cpu, max(v[2] for v in stages.values()))
        sizes.append(n)
        runs[n] = stages
    if not sizes:
        sys.exit('scale_table: no finished run under ' + args.work)
    names = [s for s in runs[sizes[0]] if s != 'whole process'] + ['whole process']
    header = ['stage'] + [f'{n} frames: wall s / CPU s / peak MiB' for n in sizes]
    pairs = list(zip(sizes, sizes[1:]))
    header += [f'exponent {a} -> {b}: wall / peak' for a, b in pairs]
    print('| ' + ' | '.join(header) + ' |')
    print('|' + '---|' * len(header))
    for name in names:
        row = [name]
        for n in sizes:
            value = runs[n].get(name)
            row.append('-' if value is None else
                       '%.1f / %.1f / %.0f' % (value[0], value[1], value[2] / 2**20))
        for a, b in pairs:
            va, vb = runs[a].get(name), runs[b].get(name)
            if va is None or vb is None:
                row.append('-')
            else:
                row.append(exponent(a, va[0], b, vb[0]) + ' / ' +
                           exponent(a, va[2], b, vb[2]))
        print('| ' + ' | '.join(row) + ' |')
    print_quality(args.work, sizes)


def load(path):
    return json.load(open(path)) if os.path.exists(path) else None


def print_quality(work, sizes):
    print()
    print('| frames | registered | position / rotation after sim3 | mesh F at 0.05 / 0.1 m, '
          'precision at 0.5 m | LIDAR-only Poisson |')
    print('|---|---|---|---|---|')
    for n in sizes:
        eval_dir = os.path.join(work, str(n), 'ws', 'eval')
        poses = load(os.path.join(eval_dir, 'poses_refined_sim3_axes.json'))
        cells = [str(n)]
        if poses:
            cells.append('%d / %d' % (poses['num_matched'], poses['num_ground_truth_frames']))
            cells.append('%.2f cm / %.3f deg' % (100 * poses['position_error_m']['mean'],
                                                 poses['rotation_error_deg']['mean']))
        else:
            cells += ['-', '-']
        for name in ('mesh_ours.json', 'mesh_lidar_poisson.json'):
            mesh = load(os.path.join(eval_dir, name))
            if not mesh:
                cells.append('-')
                continue
            t = mesh['thresholds_m']
            cells.append('%.3f / %.3f, %.3f' % (mesh['fscore'][t.index(0.05)],
                                                mesh['fscore'][t.index(0.1)],
                                                mesh['precision'][t.index(0.5)]))
        print('| ' + ' | '.join(cells) + ' |')


if __name__ == '__main__':
    main()
