#!/usr/bin/env python3
"""A whole bake against the same bake cut into shards (issue 23 item 4).

usage: sharded_bench.py SVIT_BAKE OUT_DIR NAME LEVEL SHARDS [BAKE OPTIONS...]

Runs, one after the other on this machine with every core (so each step's
wall time is its work): `svit-bake LEVEL` (the whole bake), `svit-bake plan`,
each `svit-bake shard` in turn and `svit-bake merge`, with the same
options; records each process's wall time and peak resident memory (its
own rusage, through wait4) and CPU time (user + system: the work, which
other load on the machine does not inflate as it does wall time), checks the merged OUT byte-identical to the
whole bake, and prints one JSON line: the figures sharded_report.py tables.
"""
import filecmp
import json
import os
import resource
import subprocess
import sys
import time


def run(command, log):
    """Wall and CPU seconds and peak RSS (bytes) of one process, which must succeed."""
    start = time.monotonic()
    with open(log, "w") as out:
        process = subprocess.Popen(command, stdout=out, stderr=subprocess.STDOUT)
        _, status, usage = os.wait4(process.pid, 0)
    seconds = time.monotonic() - start
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"sharded_bench: {' '.join(command)} failed; see {log}")
    return {"seconds": seconds, "cpu_seconds": usage.ru_utime + usage.ru_stime,
            "peak_rss_bytes": usage.ru_maxrss * 1024}


def same_bake(a, b):
    names = sorted(os.listdir(a))
    if names != sorted(os.listdir(b)):
        return False
    return all(name == "report.json" or filecmp.cmp(f"{a}/{name}", f"{b}/{name}", shallow=False)
               for name in names)


def main():
    bake, out, name, level, shards = sys.argv[1:6]
    options = sys.argv[6:]
    shards = int(shards)
    base = os.path.join(out, name)
    os.makedirs(base, exist_ok=True)
    whole = run([bake, level, "-o", f"{base}/whole", "--quiet", *options], f"{base}/whole.log")
    report = json.load(open(f"{base}/whole/report.json"))
    plan = run([bake, "plan", level, "-o", f"{base}/work", "--shards", str(shards), "--quiet", *options],
               f"{base}/plan.log")
    shard_runs = []
    for shard in range(shards):
        figures = run([bake, "shard", f"{base}/work", str(shard), "--quiet"], f"{base}/shard-{shard}.log")
        own = json.load(open(f"{base}/work/shard-{shard}.json"))
        figures["texels"] = own["texels"]
        figures["lighting_seconds"] = own["lighting_seconds"]
        shard_runs.append(figures)
    merge = run([bake, "merge", f"{base}/work", "-o", f"{base}/merged", "--quiet"], f"{base}/merge.log")
    plan_json = json.load(open(f"{base}/work/plan.json"))
    print(json.dumps({
        "name": name, "level": level, "options": " ".join(options), "shards": shards,
        "texels": plan_json["texels"], "passes": plan_json["passes"],
        "whole": whole, "whole_stage_seconds": report["stage_seconds"],
        "plan": plan, "shard_runs": shard_runs, "merge": merge,
        "identical": same_bake(f"{base}/merged", f"{base}/whole"),
    }))


if __name__ == "__main__":
    main()
