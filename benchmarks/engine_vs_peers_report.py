"""The report of ``engine_vs_peers.py``: speed-up at matched error, the tables and the figure.

A row is a dict with ``scene``, ``solver``, ``resolution``, ``kind`` ("engine", "limit" or
"peer"), ``time_s`` (CPU seconds per solve) and ``err`` (max relative error of A/A0 over the
outputs); engine rows also carry ``est`` (the engine's own estimate, relative) and ``err/est``
(worst true error / estimate over the outputs).

Speed-up at matched error (:func:`matched`): for every run of a peer, the fastest run of the
engine path at least as accurate; the speed-up is the peer's time over that run's time, and a
scene's figure is the **smallest** such ratio over the peer's runs (the peer's best showing).
The engine's time is never interpolated: a more accurate engine run than needed only lowers
the figure.
"""

from __future__ import annotations

import math
from pathlib import Path

ENGINE_PATHS = ("xpersson cn", "xpersson sine")
#: marker, line style and colour per solver (one style per solver across every panel)
STYLE = {
    "xpersson cn": ("o", "-", "C0"),
    "xpersson cn: own estimate": ("o", ":", "C9"),
    "xpersson sine": ("^", "-", "C2"),
    "xpersson exact": ("*", "", "C3"),
    "C march": ("D", "-", "k"),
    "scipy BDF MoL (tau)": ("s", "--", "C1"),
    "scipy LSODA MoL (tau)": ("v", "--", "C4"),
    "scipy BDF MoL (zeta)": ("x", "--", "C5"),
    "scipy BDF two-grid (tau)": ("P", "--", "C6"),
    "scipy BDF MoL (Landau)": ("s", "--", "C8"),
}


def _ok(r: dict) -> bool:
    return math.isfinite(r.get("time_s", math.nan)) and math.isfinite(r.get("err", math.nan))


def matched(rows: list[dict], scene: str, engine: str, peer: str) -> dict | None:
    """The speed-up of ``engine`` against ``peer`` at matched error on ``scene`` (module
    docstring): ``{"ratio", "peer": row, "engine": row}``, or None when no run of the engine
    path is as accurate as any run of the peer."""
    mine = [r for r in rows if r["scene"] == scene and r["solver"] == engine and _ok(r)]
    out = None
    for p in (r for r in rows if r["scene"] == scene and r["solver"] == peer and _ok(r)):
        good = [r for r in mine if r["err"] <= p["err"]]
        if not good:
            continue
        e = min(good, key=lambda r: r["time_s"])
        ratio = p["time_s"] / e["time_s"]
        if out is None or ratio < out["ratio"]:
            out = {"ratio": ratio, "peer": p, "engine": e}
    return out


def scenes_of(rows: list[dict]) -> list[str]:
    return list(dict.fromkeys(r["scene"] for r in rows))


def peers_of(rows: list[dict]) -> list[str]:
    return list(dict.fromkeys(r["solver"] for r in rows if r["kind"] == "peer"))


def worst_matched(rows: list[dict], engine: str, peer: str) -> tuple[str, dict] | None:
    """(scene, :func:`matched`) of the scene with the smallest speed-up, or None."""
    found = [(s, m) for s in scenes_of(rows) if (m := matched(rows, s, engine, peer))]
    return min(found, key=lambda sm: sm[1]["ratio"]) if found else None


def limit_ratios(rows: list[dict]) -> dict[str, list[tuple[str, float, dict]]]:
    """rtol -> [(scene, engine cn time / C march time on its levels, cn row)]."""
    out: dict[str, list] = {}
    for i, r in enumerate(rows):
        if r["kind"] != "limit" or not math.isfinite(r["time_s"]):
            continue
        cn = next(x for x in reversed(rows[:i]) if x["solver"] == "xpersson cn")
        rtol = cn["resolution"].split(",")[0].split("=")[1]
        out.setdefault(rtol, []).append((r["scene"], cn["time_s"] / r["time_s"], cn))
    return out


def _g(x: float) -> str:
    return f"{x:.3g}" if math.isfinite(x) else "-"


def headline(rows: list[dict], meta: dict) -> list[str]:
    """The "how to read it" block: worst speed-ups, the engine against its limit, the estimate."""
    lines = [
        "# Engine error versus CPU time, beside its peers and its compiled limit",
        "",
        "![error versus CPU time](work_precision.png)",
        "",
        "One panel per scene; errors below 1e-16 are drawn at 1e-16; the hollow dotted line is "
        "the `cn` runs' own error estimate at the same CPU time; the C march points are the "
        "`cn` runs' levels marched in C (same error, the compiled floor of their time).",
        "",
        "## How to read it",
        "",
        f"Run {meta['date']} on {meta['cpu']} ({meta['versions']}; C compiler: "
        f"{meta['compiler']}; engine march: {meta['march']}); command: `{meta['command']}`. "
        "CPU time (`time.process_time`) per solve, best of "
        f"{meta['rounds']} interleaved rounds, `OPENBLAS_NUM_THREADS=1`, one process. Error: "
        "max relative error of A/A0 over the outputs against the closed form. Speed-up at "
        "matched error: for each run of a peer, the fastest engine run at least as accurate; "
        "a scene's speed-up is the smallest ratio over the peer's runs, and the tables give "
        "the **worst scene**. An engine run more accurate than needed only "
        "lowers the figure.",
        "",
        "| peer | cn: worst speed-up at matched error (scene; peer run -> cn run) | "
        "sine: worst speed-up (scene) |",
        "|---|---|---|",
    ]
    for peer in peers_of(rows):
        cells = []
        for engine in ENGINE_PATHS:
            w = worst_matched(rows, engine, peer)
            if w is None:
                there = {r["scene"] for r in rows if r["solver"] == peer}
                ran = any(r["solver"] == engine and r["scene"] in there for r in rows)
                cells.append("- (no engine run as accurate)" if ran else "- (does not apply)")
                continue
            s, m = w
            p, e = m["peer"], m["engine"]
            detail = (
                f"; {p['resolution']}, err {p['err']:.1e}, {p['time_s'] * 1e3:.3g} ms -> "
                f"{e['resolution']}, err {e['err']:.1e}, {e['time_s'] * 1e3:.3g} ms"
                if engine == "xpersson cn"
                else ""
            )
            cells.append(f"**{m['ratio']:.3g}x** ({s}{detail})")
        lines.append(f"| {peer} | {cells[0]} | {cells[1]} |")
    lines += _limit_lines(rows) + _estimate_lines(rows)
    return lines


def _limit_lines(rows: list[dict]) -> list[str]:
    lim = limit_ratios(rows)
    if not lim:
        return ["", "The C march was skipped (no C compiler): no row against the limit."]
    lines = [
        "",
        "The engine against its compiled limit (the C march of `peers/c_march` on the very grid "
        "levels and steps each `cn` run marched: same node-steps, so the same error; a floor, "
        "not a solver): `cn` time / C time, worst scene.",
        "",
        "| cn rtol | worst engine / C (scene) | median over scenes | node-steps there |",
        "|---|---:|---:|---:|",
    ]
    for rtol, items in lim.items():
        s, worst, cn = max(items, key=lambda x: x[1])
        med = sorted(x[1] for x in items)[len(items) // 2]
        lines.append(
            f"| {rtol} | **{worst:.2f}** ({s}) | {med:.2f} | {cn.get('node_steps', 0):.2g} |"
        )
    return lines


def _estimate_lines(rows: list[dict]) -> list[str]:
    eng = [r for r in rows if r["kind"] == "engine" and math.isfinite(r.get("err/est", math.nan))]
    if not eng:
        return []
    lines = [
        "",
        "The engine knows its error: every engine run reports an estimate of the absolute error "
        "of A/A0 (`error_estimate`); worst true error / estimate over the outputs (errors below "
        "1e-15 not judged), per path, worst run:",
        "",
    ]
    for path in ("xpersson cn", "xpersson sine", "xpersson exact"):
        mine = [r for r in eng if r["solver"] == path]
        if mine:
            w = max(mine, key=lambda r: r["err/est"])
            if w["err/est"] == 0.0:
                lines.append(f"- {path}: every error at rounding level (< 1e-15), not judged")
                continue
            lines.append(
                f"- {path}: **{w['err/est']:.2f}** ({w['scene']}, {w['resolution']}; "
                f"true {w['err']:.1e}, estimated {w['est']:.1e} relative)"
            )
    return lines


def scene_table(rows: list[dict]) -> list[str]:
    peers = peers_of(rows)
    lines = [
        "",
        "## Speed-up of cn at matched error, per scene",
        "",
        "| scene | " + " | ".join(peers) + " |",
        "|---|" + "---:|" * len(peers),
    ]
    for s in scenes_of(rows):
        cells = []
        for p in peers:
            m = matched(rows, s, "xpersson cn", p)
            cells.append(f"{m['ratio']:.3g}x" if m else "-")
        lines.append(f"| {s} | " + " | ".join(cells) + " |")
    return lines


def write_markdown(rows: list[dict], meta: dict, path: Path) -> None:
    lines = headline(rows, meta) + scene_table(rows)
    lines += [
        "",
        "## Every run",
        "",
        "`est`: the engine's own error estimate, relative (max over the outputs of "
        "`error_estimate / A`); `err/est`: worst true / estimated over the outputs. C march "
        "rows: the error of the `cn` run whose levels they march.",
        "",
        "| scene | solver | resolution | CPU time [ms] | err | est | err/est | node-steps |",
        "|---|---|---|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        steps = r.get("node_steps")
        lines.append(
            f"| {r['scene']} | {r['solver']} | {r['resolution']} | {_g(r['time_s'] * 1e3)} | "
            f"{r.get('err', math.nan):.2e} | {_g(r.get('est', math.nan))} | "
            f"{_g(r.get('err/est', math.nan))} | {f'{steps:.2g}' if steps else ''} |"
            + (f" {r['error']}" if "error" in r else "")
        )
    path.write_text("\n".join(lines) + "\n")


def plot(rows: list[dict], path: Path) -> None:
    """One panel per scene: error (log) against CPU time (log), one style per solver."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = scenes_of(rows)
    ncol = 3 if len(names) > 4 else 2
    nrow = math.ceil(len(names) / ncol)
    fig, axes = plt.subplots(
        nrow, ncol, figsize=(3.8 * ncol, 2.9 * nrow + 0.7), squeeze=False, sharex=True,
        sharey=True, layout="constrained",
    )  # fmt: skip
    for ax, name in zip(axes.flat, names, strict=False):
        _panel(ax, [r for r in rows if r["scene"] == name and _ok(r)])
        ax.set_title(name, fontsize=8)
    for ax in axes.flat[len(names) :]:
        ax.set_visible(False)
    for ax in axes[:, 0]:
        ax.set_ylabel("max rel. error of A/A0", fontsize=8)
    for ax in axes.flat[max(0, len(names) - ncol) : len(names)]:
        ax.set_xlabel("CPU time per solve [s]", fontsize=8)
        ax.xaxis.set_tick_params(labelbottom=True)
    handles = {}
    for ax in axes.flat:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            handles.setdefault(lab, h)
    order = [k for k in STYLE if k in handles]
    fig.legend([handles[k] for k in order], order, loc="outside lower center", ncol=4, fontsize=7)
    fig.get_layout_engine().set(h_pad=0.02, w_pad=0.02)
    fig.savefig(path, dpi=80, metadata={"Software": None})
    plt.close(fig)


def _panel(ax, rows: list[dict]) -> None:
    groups: dict[str, list[tuple[float, float]]] = {}
    for r in rows:
        groups.setdefault(r["solver"], []).append((r["time_s"], r["err"]))
        if r["solver"] == "xpersson cn" and math.isfinite(r.get("est", math.nan)):
            groups.setdefault("xpersson cn: own estimate", []).append((r["time_s"], r["est"]))
    for label in (k for k in STYLE if k in groups):
        pts = groups[label]  # in run order (rtol, N): the error need not fall with time
        marker, ls, colour = STYLE[label]
        hollow = label.endswith("estimate")
        ax.loglog(
            [t for t, _ in pts], [max(e, 1e-16) for _, e in pts], marker=marker, ls=ls or "none",
            color=colour, ms=6 if marker == "*" else 4, label=label,
            mfc="none" if hollow else colour, lw=1,
        )  # fmt: skip
    ax.grid(True, which="major", lw=0.3, alpha=0.5)
    ax.tick_params(labelsize=7)
