#!/usr/bin/env python3
"""Tables sharded_bench.py's figures into docs/bench/sharded_bench.md (between
its `<!-- sharded_bench.sh: begin -->` and `<!-- sharded_bench.sh: end -->`
markers, doc_section.py). usage: sharded_report.py DOC RESULTS.jsonl"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from doc_section import put_section  # noqa: E402


def mb(b):
    return f"{b / 1e6:.0f} MB"


def step(figures):
    return f"{figures['seconds']:.1f} s ({figures['cpu_seconds']:.1f} s CPU), {mb(figures['peak_rss_bytes'])}"


def case_rows(r):
    shards = r["shard_runs"]
    cpu = [s["cpu_seconds"] for s in shards]
    walls = [s["seconds"] for s in shards]
    work = r["plan"]["cpu_seconds"] + sum(cpu) + r["merge"]["cpu_seconds"]
    whole = r["whole"]["cpu_seconds"]
    return [
        f"| {r['name']} | {r['shards']} | {r['texels']:,} | {r['passes']} | {step(r['whole'])} "
        f"| {step(r['plan'])} "
        f"| {min(walls):.1f}–{max(walls):.1f} s ({min(cpu):.1f}–{max(cpu):.1f} s CPU), up to "
        f"{mb(max(s['peak_rss_bytes'] for s in shards))} | {step(r['merge'])} "
        f"| {work:.1f} s against {whole:.1f} s ({100 * (work / whole - 1):+.1f} %) "
        f"| {max(cpu) / (sum(cpu) / len(cpu)):.2f} ({max(walls) / (sum(walls) / len(walls)):.2f}) "
        f"| {'yes' if r['identical'] else '**no**'} |"
    ]


def main():
    path, results = sys.argv[1], sys.argv[2]
    rows = [json.loads(line) for line in open(results) if line.strip()]
    lines = ["| level | shards | texels | passes | whole bake: wall (CPU), peak memory | plan | each shard | merge "
             "| total work, CPU: plan + shards + merge against the whole bake (overhead) "
             "| balance: longest / mean shard, CPU (wall) | merged OUT byte-identical |",
             "|---|---:|---:|---:|---|---|---|---|---|---|---|"]
    for r in rows:
        lines += case_rows(r)
    options = "; ".join(f"{r['name']}: `{r['options']}`" for r in rows)
    section = ("Each step run on the 2-core machine with both cores, one after the other. Work is CPU time "
               "(user + system, from each process's rusage): what N machines spend together, and unlike wall "
               "time not inflated by other load on the machine (wall times are given too). Peak memory is each "
               "process's maximum resident set. The balance is the longest shard against the mean (targets: "
               f"overhead ≤ 10 %, balance ≤ 1.2). Options: {options}.\n\n" + "\n".join(lines) + "\n")
    put_section(path, "sharded_bench.sh", section)
    print("\n".join(lines))


if __name__ == "__main__":
    main()
