#!/usr/bin/env python3
"""Markdown table of every run recorded in results_minpeak_hi.jsonl (written by minpeak_spin_hi.py).
usage: python make_table.py [results_minpeak_hi.jsonl]   (later duplicates of the same run replace earlier ones)"""
import os
import sys
import json

HERE = os.path.dirname(os.path.abspath(__file__))
fn = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, 'results_minpeak_hi.jsonl')
rows = {}
for line in open(fn):
    r = json.loads(line)
    rows[(r['scheme'], r['start'], r['N'], r['correction_round'])] = r    # keep the latest


def start_name(s):
    return {'ref': 'ref (45°, 0.75 turn, −)'}.get(s, s.replace('npz:sols/', 'warm ').replace('.npz', ''))


print('| N | orientation scheme | start | flip target | P = NLP peak (nodes+midpoints) | peak at nodes '
      '(DOP853 attitude) | dense peak (16/interval) | flip error after DOP853 (rad) | twist (°) | branch | '
      'bend turns | max bend (°) | IPOPT iters | wall (s) | status |')
print('|' + '---|' * 15)
for (sch, st, N, c), r in rows.items():
    tgt = 'Rz(π)' if c == 0 else f'corrected ×{c}'
    print(f"| {N} | {sch} | {start_name(st)} | {tgt} | {r['P']:.7f} | {r['peak_nodes']:.7f} | "
          f"{r['peak_dense']:.7f} | {r['flip_err_rad']:.2e} | {r['twist_deg']:+.7f} | "
          f"{'with' if r['twist_deg'] > 0 else 'against'} | {r['turns']:+.3f} | {r['max_bend_deg']:.2f} | "
          f"{r['iters']} | {r['wall_s']:.0f} | {r['status'].replace('_', ' ')} |")
