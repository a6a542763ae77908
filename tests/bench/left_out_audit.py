#!/usr/bin/env python3
"""Tabulates what each level's bake and runtime hold and leave out.

usage: left_out_audit.py OUT_DIR LEVEL...  (OUT_DIR/LEVEL/{bake/report.json,
stats.json} written by left_out_audit.sh). Writes OUT_DIR/audit.json and
OUT_DIR/audit.md and prints the markdown.
"""
import json
import os
import sys


def size(b):
    if b >= 1048576:
        return f"{b / 1048576:.1f} MiB"
    if b >= 1024:
        return f"{b / 1024:.1f} KiB"
    return f"{b} B"


def level_audit(out_dir, name):
    bake_dir = os.path.join(out_dir, name, "bake")
    report = json.load(open(os.path.join(bake_dir, "report.json")))
    stats = json.load(open(os.path.join(out_dir, name, "stats.json")))
    pages = [f for f in sorted(os.listdir(bake_dir)) if f.endswith(".exr")]
    return {
        "level": name,
        "bake_file_bytes": os.path.getsize(os.path.join(bake_dir, "bake.svit")),
        "lightmap_files": {f: os.path.getsize(os.path.join(bake_dir, f)) for f in pages},
        "sections_written": report["sections_written"],
        "sections_left_out": report["sections_left_out"],
        "runtime": stats["resources"]["runtime"],
        "renderer": stats["resources"]["renderer"],
    }


def left_out_text(items, key):
    """Names left out, grouped by reason: "a, b (reason); c (reason)"."""
    by_reason = {}
    for item in items:
        by_reason.setdefault(item["reason"], []).append(item[key])
    return "; ".join(f"{', '.join(names)} ({reason})" for reason, names in by_reason.items()) or "nothing"


def summary(audits):
    lines = ["| level | bake: file + EXR | bake left out | runtime: GPU / host | runtime left out | "
             "renderer GPU | renderer left out |", "|---|---:|---|---:|---|---:|---|"]
    for a in audits:
        bake = a["bake_file_bytes"] + sum(a["lightmap_files"].values())
        held = [u for u in a["runtime"] if u["allocated"]]
        gpu = sum(u["gpu_bytes"] for u in held)
        host = sum(u["cpu_bytes"] for u in held)
        drawn = sum(u["gpu_bytes"] for u in a["renderer"] if u["allocated"])
        lines.append(f"| {a['level']} | {size(bake)} | "
                     f"{left_out_text(a['sections_left_out'], 'section')} | {size(gpu)} / {size(host)} | "
                     f"{left_out_text([u for u in a['runtime'] if not u['allocated']], 'name')} | {size(drawn)} | "
                     f"{left_out_text([u for u in a['renderer'] if not u['allocated']], 'name')} |")
    return "\n".join(lines) + "\n"


def details(audits):
    out = []
    for a in audits:
        out.append(f"### {a['level']}\n")
        out.append("| part | item | held | GL objects | GPU | host | why / why not |")
        out.append("|---|---|---|---:|---:|---:|---|")
        for s in a["sections_written"]:
            out.append(f"| bake.svit | {s['section']} ({s['tag']}) | yes | | | {size(s['bytes'])} | {s['holds']} |")
        for s in a["sections_left_out"]:
            out.append(f"| bake.svit | {s['section']} | no | | | | {s['reason']} |")
        for f, b in a["lightmap_files"].items():
            out.append(f"| bake | {f} | yes | | | {size(b)} | lightmap page (fp32 RGB EXR) |")
        for part in ("runtime", "renderer"):
            for u in a[part]:
                out.append(f"| {part} | {u['name']} | {'yes' if u['allocated'] else 'no'} | {u['gl_objects']} | "
                           f"{size(u['gpu_bytes'])} | {size(u['cpu_bytes'])} | {u['reason']} |")
        out.append("")
    return "\n".join(out) + "\n"


def main():
    out_dir, levels = sys.argv[1], sys.argv[2:]
    audits = [level_audit(out_dir, name) for name in levels]
    json.dump(audits, open(os.path.join(out_dir, "audit.json"), "w"), indent=1)
    text = summary(audits) + "\n" + details(audits)
    open(os.path.join(out_dir, "audit.md"), "w").write(text)
    print(text)


if __name__ == "__main__":
    main()
