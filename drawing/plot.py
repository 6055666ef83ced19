#!/usr/bin/env python3
"""Draws aoeval plots: plot.py SPEC.json OUT.png|OUT.svg [more pairs] (see drawing/plot.h).

plot.py --serve: a pre-started worker (drawing/plot_workers.h). It imports matplotlib at once,
then reads one job per line from stdin, "SPEC.json<TAB>OUT.png", and answers one line per job on
stdout, "ok" or "error: <message>"; it exits at the end of stdin.

matplotlib is the plotting library (Debian python3-matplotlib): proper axes, log scales, legends,
error bars and vector output. The C++ side decides what to plot; this file only draws it.
"""
import io
import json
import os
import signal
import sys

import matplotlib

matplotlib.use("Agg")  # headless: no display on CI
import matplotlib.pyplot as plt  # noqa: E402


def make_figure(spec):
    panels = spec.get("panels") or [spec]  # "panels": plots side by side, one axes each
    fig, axes = plt.subplots(1, len(panels),
                             figsize=(spec.get("width_in", 7.0), spec.get("height_in", 4.5)))
    for ax, panel in zip(axes if len(panels) > 1 else [axes], panels):
        draw_axes(ax, panel)
    fig.tight_layout()
    return fig


def draw(spec, out_path):
    fig = make_figure(spec)
    root, ext = os.path.splitext(out_path)
    tmp = root + ".tmp" + str(os.getpid()) + ext
    fig.savefig(tmp, dpi=spec.get("dpi", 110))
    plt.close(fig)
    os.replace(tmp, out_path)


def draw_axes(ax, spec):
    series = spec.get("series", [])
    bars = [s for s in series if s.get("kind") == "bar"]
    bar_width = 0.8 / max(1, len(bars))
    bar_index = 0
    for s in series:
        kind = s.get("kind", "line")
        x, y = s["x"], s["y"]
        style = {}
        if s.get("colour"):
            style["color"] = s["colour"]
        label = s.get("label") or None
        err = s.get("y_error")
        if kind == "bar":
            offset = (bar_index - (len(bars) - 1) / 2.0) * bar_width
            bar_index += 1
            ax.bar([v + offset for v in x], y, bar_width, yerr=err, label=label, capsize=3, **style)
            continue
        marker = s.get("marker") or ("o" if kind == "scatter" else ".")
        linestyle = "none" if kind == "scatter" else ("--" if s.get("dashed") else "-")
        if kind == "step":
            ax.step(x, y, where="post", label=label, linestyle=linestyle, **style)
        elif err:
            ax.errorbar(x, y, yerr=err, label=label, marker=marker, linestyle=linestyle,
                        capsize=3, **style)
        else:
            ax.plot(x, y, label=label, marker=marker, linestyle=linestyle, **style)
        highlight = s.get("highlight")
        if highlight:
            hx = [a for a, h in zip(x, highlight) if h]
            hy = [b for b, h in zip(y, highlight) if h]
            order = sorted(range(len(hx)), key=lambda i: hx[i])
            ax.plot([hx[i] for i in order], [hy[i] for i in order], color="black",
                    linestyle=":", marker="D", markerfacecolor="none", markersize=9,
                    label=(label + " (Pareto front)") if label else "Pareto front")
        for xi, yi, text in zip(x, y, s.get("point_labels") or []):
            if text:
                ax.annotate(text, (xi, yi), textcoords="offset points", xytext=(4, 4), fontsize=7)
    categories = spec.get("categories") or []
    if categories:
        ax.set_xticks(range(len(categories)))
        ax.set_xticklabels(categories, rotation=20 if len(categories) > 4 else 0, ha="right"
                           if len(categories) > 4 else "center")
    if spec.get("log_x"):
        ax.set_xscale("log")
    if spec.get("log_y"):
        ax.set_yscale("log")
    ax.set_title(spec.get("title", ""))
    ax.set_xlabel(spec.get("x_label", ""))
    ax.set_ylabel(spec.get("y_label", ""))
    ax.grid(True, which="both", alpha=0.3)
    if any(s.get("label") for s in series):
        ax.legend(fontsize=8)
    notes = spec.get("notes") or []
    if notes:
        ax.text(0.01, 0.01, "\n".join(notes), transform=ax.transAxes, fontsize=7,
                va="bottom", ha="left", bbox=dict(facecolor="white", alpha=0.8, linewidth=0))


def draw_file(spec_path, out_path):
    with open(spec_path, encoding="utf-8") as f:
        spec = json.load(f)
    draw(spec, out_path)


def serve():
    # Ctrl-C reaches the whole process group; the harness decides what an interrupt stops, and a
    # worker killed mid-run would lose the report's charts.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    # A throwaway plot first: matplotlib's first drawing loads fonts and sets up the renderer
    # (a quarter of a second), which a worker does before it is asked for a chart.
    warm_up = {"title": "warm-up", "x_label": "x", "y_label": "y", "log_y": True,
               "notes": ["n"], "series": [{"label": "a", "kind": "line", "x": [1, 2], "y": [1, 2]},
                                         {"label": "b", "kind": "bar", "x": [0], "y": [1]}]}
    fig = make_figure(warm_up)
    fig.savefig(io.BytesIO(), format="png", dpi=50)
    plt.close(fig)
    for line in sys.stdin:
        spec_path, _, out_path = line.rstrip("\n").partition("\t")
        try:
            draw_file(spec_path, out_path)
            answer = "ok"
        except Exception as e:  # noqa: BLE001 - the message goes back to the harness
            plt.close("all")  # a long-lived worker must not keep a failed plot's figure
            answer = "error: " + " ".join(f"{type(e).__name__}: {e}".split())
        sys.stdout.write(answer + "\n")
        sys.stdout.flush()


def main():
    if sys.argv[1:] == ["--serve"]:
        serve()
        return
    # Pairs of arguments: several plots from one process pay matplotlib's import once.
    args = sys.argv[1:]
    if not args or len(args) % 2:
        sys.exit("usage: plot.py SPEC.json OUT.png|OUT.svg [SPEC.json OUT.png|OUT.svg ...]")
    for spec_path, out_path in zip(args[0::2], args[1::2]):
        draw_file(spec_path, out_path)


if __name__ == "__main__":
    main()
