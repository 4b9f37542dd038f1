"""The placement report: every measured step as JSON and as a markdown table beside it."""

import json
from pathlib import Path

from .edit import write_atomic


def report_paths(args):
    if args.report:
        j = Path(args.report)
    else:
        o = Path(args.out)
        j = o.with_name(o.stem + ".placement.json")
    return j, j.with_suffix(".md")


def write_report(args, report):
    j, md = report_paths(args)
    write_atomic(j, text=json.dumps(report, indent=2) + "\n")
    views = report["views"]
    lines = ["# speculum-probes place", "",
             f"Scene `{report['scene']}`, views {', '.join(views)} at {report['size']}, reference {report.get('reference') or str(report['spp']) + ' spp'}; "
             f"budget: mean PSNR >= {report['budget_db']:g} dB; CMO kind `{report['kind']}`; "
             f"{'met' if report['met'] else 'NOT met'} with {report['final']['count']} CMO(s), "
             f"{report['final']['mean_psnr_db']:.2f} dB (baseline {report['baseline']['mean_psnr_db']:.2f} dB); "
             f"{report['measurements']} measurements in {report['seconds']:.0f} s.", "",
             "| step | action | detail | CMOs | resolutions | mean PSNR dB | " + " | ".join(views) +
             " | reflection ms | kept |",
             "|---|---|---|---|---|---|" + "---|" * len(views) + "---|---|"]
    for s in report["steps"]:
        lines.append(f"| {s['step']} | {s['action']} | {s['detail']} | {s['count']} | "
                     f"{','.join(map(str, s['resolutions'])) or '-'} | {s['mean_psnr_db']:.2f} | " +
                     " | ".join(f"{s['per_view_psnr_db'][v]:.2f}" for v in views) +
                     f" | {s['reflection_ms']:.2f} | {'yes' if s['accepted'] else ''} |")
    write_atomic(md, text="\n".join(lines) + "\n")
