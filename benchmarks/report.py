"""Writes the benchmark results: ``results.json`` (every raw number and the machine facts) and
``performance.md`` (tables and links to ``figures/performance_*.png``, matplotlib Agg).

A full run writes ``benchmarks/results.json``, ``docs/performance.md`` and ``docs/figures/``;
``--smoke`` (or ``--out DIR``) writes the same files into one folder instead. Without
matplotlib the plots are left out and the Markdown says so.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from benchmarks import pyplot

__all__ = ["write", "markdown", "HEADER", "DOCS", "RESULTS"]

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
RESULTS = ROOT / "benchmarks" / "results.json"
HEADER = "<!-- written by python -m benchmarks; do not edit by hand -->"
CALLS = ("eval", "pdf", "eval_pdf", "sample")


# --- formatting ------------------------------------------------------------------------------
def _rate(x) -> str:
    """Evaluations per second, e.g. ``5.85 M/s``."""
    if x is None:
        return "–"
    for scale, unit in ((1e9, "G/s"), (1e6, "M/s"), (1e3, "k/s")):
        if x >= scale:
            return f"{x / scale:.3g} {unit}"
    return f"{x:.3g} /s"


def _time(seconds) -> str:
    if seconds is None:
        return "–"
    for scale, unit in ((1.0, "s"), (1e-3, "ms"), (1e-6, "µs")):
        if seconds >= scale:
            return f"{seconds / scale:.3g} {unit}"
    return f"{seconds * 1e9:.3g} ns"


def _n(n: int) -> str:
    e = math.log10(n)
    return f"10^{e:.0f}" if e == int(e) else f"{n}"


def _load(x) -> str:
    return "?" if x is None else f"{x:.2f}"


def _threads(t) -> str:
    return "default" if t is None else str(t)


def _cell(row) -> str:
    """``rate (passes)`` of a measured row, or why it is missing."""
    if row is None:
        return "–"
    if "skipped" in row:
        return "skipped"
    if "error" in row:
        return "error"
    return f"{_rate(row['evals_per_s'])} ({row['memory_passes']:.0f})"


def _failed(section) -> str | None:
    if section is None:
        return "not run (see `--sections`)"
    if "error" in section and "rows" not in section:
        return f"failed:\n\n```\n{section['error'].strip()}\n```"
    return None


def _opening(title: str, label: str, section) -> tuple[list, list | None]:
    """(the heading lines of a section, None), or (them, the lines that say why ``section``
    is missing)."""
    out = [f"## {title}", ""]
    failed = _failed(section)
    return out, (out + [f"{label} section {failed}", ""] if failed else None)


def _clean(x):
    """JSON-safe copy: inf/nan -> None, tuples -> lists."""
    if isinstance(x, dict):
        return {str(k): _clean(v) for k, v in x.items()}
    if isinstance(x, list | tuple):
        return [_clean(v) for v in x]
    if isinstance(x, float) and not math.isfinite(x):
        return None
    return x


# --- plots -----------------------------------------------------------------------------------


def _plot_throughput(plt, tp: dict, path: Path) -> bool:
    ref, cpus = tp["reference_size"], tp["threads"][0]
    rows = [r for r in tp["rows"] if r.get("n") == ref and r.get("threads") == cpus
            and "evals_per_s" in r]
    cases = list(dict.fromkeys(r["case"] for r in rows))
    if not cases:
        return False
    calls = [c for c in CALLS if any(r["call"] == c for r in rows)]
    fig, ax = plt.subplots(figsize=(8, 0.35 * len(cases) * len(calls) / 2 + 1.5))
    height = 0.8 / len(calls)
    for j, call in enumerate(calls):
        rate = {r["case"]: r["evals_per_s"] for r in rows if r["call"] == call}
        ys = [i + j * height for i in range(len(cases))]
        ax.barh(ys, [rate.get(c, 0.0) for c in cases], height=height, label=call)
    ax.set_yticks([i + 0.4 - height / 2 for i in range(len(cases))], cases, fontsize=8)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlabel(f"evaluations per second ({_n(ref)} pairs, {_threads(cpus)} threads)")
    ax.legend(fontsize=8)
    ax.grid(axis="x", which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


def _plot_active(plt, al: dict, path: Path) -> bool:
    rows = [r for r in al["rows"] if "eval" in r]
    if not rows:
        return False
    fig, ax = plt.subplots(figsize=(6, 4))
    for call in ("eval", "sample"):
        ax.plot([r["k"] for r in rows], [r[call]["seconds"] for r in rows], "o-", label=call)
    plain = [r for r in rows if "plain_eval" in r]
    if plain:
        ax.plot([r["k"] for r in plain], [r["plain_eval"]["seconds"] for r in plain], "x--",
                label="eval, plain Sum of the active lobes")
    ax.set_xlabel(f"active lobes k (of K = {al['K']})")
    ax.set_ylabel(f"seconds for {_n(al['n'])} pairs")
    ax.set_xticks(range(al["K"] + 1))
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return True


# --- sections --------------------------------------------------------------------------------
def _header(results: dict, plots: bool) -> list:
    m = results["machine"]
    gib = f", {m['memory_bytes'] / 2**30:.0f} GiB" if m.get("memory_bytes") else ""
    commit = (m.get("git_commit") or "unknown")[:12]
    if m.get("git_dirty"):
        commit += " + uncommitted changes"
    out = [HEADER, "", "# Performance", ""]
    if results.get("smoke"):
        out += ["*Smoke run (`python -m benchmarks --smoke`): tiny sizes and 2 runs; the "
                "numbers only show that the benchmark works.*", ""]
    out += [f"Measured {m['date_utc']} by `python -m benchmarks` in "
            f"{results['total_seconds']:.0f} s "
            f"({', '.join(f'{k} {v:.0f} s' for k, v in results['section_seconds'].items())})"
            + ("" if not results.get("measured") else "; later parts: " + ", ".join(
                f"{k} on {v}" for k, v in results["measured"].items()
                if v != m["date_utc"])) + ".",
            "",
            f"- Machine: {m['cpu_model']}, {m['cores']} usable cores{gib}; {m['platform']}; "
            f"1-minute load average {_load(m.get('load_average_1min'))} at the start, "
            f"{_load(results.get('load_average_1min_end'))} at the end (other processes "
            "running at the same time slow the measurements down)",
            f"- Versions: Python {m['python']}, NumPy {m['numpy']}, SciPy {m['scipy']}, "
            f"adobe_bsdf {m['adobe_bsdf']} (commit {commit}), Mitsuba {m['mitsuba']}, "
            f"Dr.Jit {m['drjit']}",
            "- Inputs: `wo`, `wi` uniform on the unit sphere with `wo.z` made positive (so "
            "every lobe sees reflection and transmission), uniforms in [0, 1) for `sample`; "
            "float64, seed 0.",
            "- A time is the median of several runs of `time.perf_counter` around one call "
            "(a call shorter than 5 ms is repeated within a run and averaged). Batches larger "
            "than 10^6 pairs are passed in slices of 10^6 whose times are summed, which caps "
            "the memory of a call.",
            "- *Memory passes*: the time divided by that of one `np.add(a, b, out=c)` over "
            "float64 arrays of shape (n, 3) with the same n (one read of two arrays and one "
            "write of a third, single-threaded), measured in the same run: a machine-"
            "independent cost unit.",
            "- Threads: `adobe_bsdf.config.options(threads=...)`; \"all\" is every CPU of the "
            "process. The results are bit-identical for any thread count.",
            ""]
    if not plots:
        out += ["*Plots left out: matplotlib is not installed (`pip install "
                "'adobe_bsdf[bench]'`).*", ""]
    return out


def _mitsuba_rows(mi: dict | None) -> dict:
    if not mi or not mi.get("available"):
        return {}
    return {(r["lobe"], r["call"]): r for r in mi["rows"]}


def _headline(results: dict) -> list:
    hl = results.get("headline")
    out, missing = _opening("Headline", "Headline", hl)
    if missing:
        return missing
    mi = _mitsuba_rows(results.get("mitsuba"))
    rows = {(r["lobe"], r["call"], r["threads"]): r for r in hl["rows"]}
    calls = [c for c in CALLS + ("eval_above",) if any(r["call"] == c for r in hl["rows"])]
    out += [f"`eval`, `pdf`, `eval_pdf` and `sample` on {_n(hl['n'])} pairs: evaluations per "
            "second (memory passes in parentheses). *eval_above*: `eval` on the same pairs "
            "with `wi` mirrored above the surface, where every sample lies (on the uniform "
            "pairs a one-sided lobe skips the half of them outside its support). *NumPy / "
            "Mitsuba* is the ratio of the "
            "times of the same call (NumPy float64 against Mitsuba 3 `llvm_ad_rgb` float32, "
            "both on all cores); Mitsuba uses separable Smith masking, the NumPy lobes their "
            "default height-correlated form.", ""]
    for key, label in hl["labels"].items():
        out.append(f"- **{key}**: {label}")
    out += ["", "| lobe | threads | " + " | ".join(calls)
            + " | eval time | NumPy / Mitsuba (eval, pdf, sample) |",
            "|---|---|" + "---|" * len(calls) + "---|---|"]
    for key in hl["labels"]:
        for threads in hl["threads"]:
            cells = [_cell(rows.get((key, c, threads))) for c in calls]
            ev = rows.get((key, "eval", threads), {})
            ratios = []
            for c in ("eval", "pdf", "sample"):
                r, m = rows.get((key, c, threads), {}), mi.get((key, c))
                ratios.append(f"{r['seconds'] / m['median_seconds']:.0f}" if m and "seconds"
                              in r else "–")
            thr = "all" if threads is not None and threads > 1 else _threads(threads)
            out.append(f"| {key} | {thr} | " + " | ".join(cells)
                       + f" | {_time(ev.get('seconds'))} | {', '.join(ratios)} |")
    out += ["", f"One memory pass at {_n(hl['n'])}: {_time(hl['memory_pass_seconds'])}.", ""]
    for key in hl["labels"]:
        threads = hl["threads"][0]
        s, e, a = (rows.get((key, c, threads), {}).get("seconds")
                   for c in ("sample", "eval", "eval_above"))
        if s and e and a:
            out.append(f"- {key} (all threads): sample / eval = {s / e:.2f}, sample / "
                       f"eval_above = {s / a:.2f} (bound of sample / eval: 1.6)")
    out.append("")
    if not hl.get("has_config"):
        out += ["(This commit has no `adobe_bsdf.config`: default threading only.)", ""]
    return out


#: targets of the headline eval: (largest NumPy / Mitsuba time ratio, largest memory passes)
TARGETS = {"conductor": (10.0, 20.0), "dielectric": (15.0, None)}


def _before_after(results: dict) -> list:
    """The headline lobes before the performance work (``benchmarks.baseline``) and now."""
    out = ["## Before and after", ""]
    base = results.get("baseline")
    failed = _failed(base)
    if failed:
        return out + [f"Baseline section {failed}", ""]
    hl = results.get("headline")
    if _failed(hl):
        return out + ["Needs the headline section.", ""]
    mi = _mitsuba_rows(results.get("mitsuba"))
    inter_rows = [r for r in ((results.get("mitsuba") or {}).get("interleaved") or {}).get(
        "rows", []) if r["call"] == "eval"]
    inter = {r["lobe"]: r["ratio"] for r in inter_rows}
    inter_seconds = {r["lobe"]: r["mitsuba_seconds"] for r in inter_rows}
    add = hl["memory_pass_seconds"]
    before = {(r["lobe"], r["call"]): r for r in base["headline"]["rows"] if "seconds" in r}
    after = {(r["lobe"], r["call"], r["threads"]): r for r in hl["rows"] if "seconds" in r}
    cpus = hl["threads"][0]
    out += [f"*Before*: the library at commit {base['commit'][:12]} (\"{base['subject']}\", "
            "the last commit before the performance work), timed by the same code in a "
            "subprocess of this run (its default threading: it has no thread pool). *After*: "
            f"this commit, all threads ({_threads(cpus)}) and 1 thread. {_n(hl['n'])} pairs; "
            f"memory passes against this run's `np.add` ({_time(add)}); *× Mitsuba*: time / "
            "Mitsuba's median time of the same call in this run.", "",
            "| lobe | call | before | after, all threads | after, 1 thread | speed-up | "
            "memory passes before → after | × Mitsuba before → after |",
            "|---|---|---|---|---|---|---|---|"]
    verdicts = []
    for key in hl["labels"]:
        for call in CALLS:
            b, a = before.get((key, call)), after.get((key, call, cpus))
            if a is None:
                continue
            a1 = after.get((key, call, 1)) if cpus != 1 else None
            m = mi.get((key, call))

            def pair(fmt, value, b=b, a=a):
                return f"{fmt(value(b)) if b else '–'} → {fmt(value(a))}"

            speed_up = f"{b['seconds'] / a['seconds']:.2f}" if b else "–"
            passes = pair("{:.0f}".format, lambda r: r["seconds"] / add)
            vs_mitsuba = pair("{:.1f}".format, lambda r, m=m: r["seconds"] /
                              m["median_seconds"]) if m else "–"
            out.append(f"| {key} | {call} | {_time(b['seconds']) if b else '–'} | "
                       f"{_time(a['seconds'])} | {_time(a1['seconds']) if a1 else '–'} | "
                       f"{speed_up} | {passes} | {vs_mitsuba} |")
            if call == "eval" and key in TARGETS:
                max_ratio, max_passes = TARGETS[key]
                parts = []
                r, how = inter.get(key), "interleaved"
                if r is None and m:
                    r, how = a["seconds"] / m["median_seconds"], "separate sections"
                if r is not None:
                    parts.append(f"{r:.1f}× Mitsuba ({how}; target ≤ {max_ratio:g}×: "
                                 f"{'met' if r <= max_ratio else 'not met'})")
                if max_passes is not None:
                    p = a["seconds"] / add
                    parts.append(f"{p:.1f} memory passes (target ≤ {max_passes:g}: "
                                 f"{'met' if p <= max_passes else 'not met'})")
                two = ((results.get("chunks") or {}).get("two_processes") or {}).get(key)
                mitsuba = m and (inter_seconds.get(key) or m["median_seconds"])
                if two and mitsuba:
                    parts.append(f"ceiling without an interpreter lock (two processes, "
                                 f"chunk sweep): {_time(two)}, {two / mitsuba:.1f}× Mitsuba")
                verdicts.append(f"- {key} `eval`: " + "; ".join(parts))
    return out + [""] + verdicts + [""]


def _chunks(results: dict) -> list:
    from benchmarks import chunks

    out, missing = _opening("Chunk size and threads", "Chunks", results.get("chunks"))
    if missing:
        return missing
    return out + chunks.markdown(results["chunks"])


def _mitsuba(results: dict) -> list:
    mi = results.get("mitsuba")
    out, missing = _opening("Mitsuba 3 reference", "Mitsuba", mi)
    if missing:
        return missing
    if not mi.get("available"):
        reason = " ".join(mi["reason"].split())
        return out + [f"**Not available** on this machine: {reason}", ""]
    hl = results.get("headline") or {}
    numpy_all = {(r["lobe"], r["call"]): r for r in hl.get("rows", [])
                 if r["threads"] == (hl.get("threads") or [None])[0] and "seconds" in r}
    cache = mi.get("kernel_cache", {})
    out += [f"The headline lobes as Mitsuba {mi['mitsuba']} (Dr.Jit {mi['drjit']}) plugins "
            f"(`roughconductor` ggx alpha_u 0.5, alpha_v 0.1, gold eta / k, visible-normal "
            f"sampling; `roughdielectric` ggx alpha 0.3, int_ior 1.5, ext_ior 1), variant "
            f"`{mi['variant']}`, on the same {_n(mi['n'])} pairs converted to float32. Mitsuba "
            f"computes in **float32 on all cores** ({mi['dr_threads']} Dr.Jit threads), the "
            "NumPy lobes in float64. Measured in a subprocess with "
            f"`DRJIT_LIBLLVM_PATH={mi['libllvm']}`.", "",
            "A time is the call followed by `dr.eval(result); dr.sync_thread()`. The *first "
            "call* traces, JIT-compiles (LLVM) and runs the kernel; it ran with an empty "
            f"Dr.Jit kernel cache ({cache.get('state', '?')}; "
            f"{cache.get('kernels_written', '?')} kernels written), so it includes the "
            "compilation; with a warm `~/.drjit` cache it would be shorter. *Median* is over "
            f"{mi['runs']} later calls.", "",
            "| lobe | call | first call (JIT + run) | median | evaluations/s | NumPy (all "
            "threads) | NumPy / Mitsuba |", "|---|---|---|---|---|---|---|"]
    for r in mi["rows"]:
        npy = numpy_all.get((r["lobe"], r["call"]))
        ratio = f"{npy['seconds'] / r['median_seconds']:.0f}" if npy else "–"
        out.append(f"| {r['lobe']} | {r['call']} | {_time(r['first_seconds'])} | "
                   f"{_time(r['median_seconds'])} | {_rate(r['evals_per_s'])} | "
                   f"{_time(npy['seconds']) if npy else '–'} | {ratio} |")
    inter = mi.get("interleaved")
    if inter:
        out += ["", f"**Interleaved** ({inter['rounds']} rounds; `benchmarks.mitsuba_bench."
                "_interleaved`): in each round every call runs in NumPy (all threads, after "
                "one untimed call) and then in the waiting Mitsuba worker, so that both see "
                "the same phase of a shared machine. These ratios are the ones compared with "
                "the targets.", "",
                "| lobe | call | NumPy median | Mitsuba median | NumPy / Mitsuba |",
                "|---|---|---|---|---|"]
        for r in inter["rows"]:
            out.append(f"| {r['lobe']} | {r['call']} | {_time(r['numpy_seconds'])} | "
                       f"{_time(r['mitsuba_seconds'])} | {r['ratio']:.1f} |")
    agree = mi.get("agreement", {})
    if agree and "error" not in agree:
        out += ["", "Same lobes? Mitsuba's `eval` (cosine included) against the NumPy lobes "
                "with `masking=\"separable\"` on the first pairs: max relative difference "
                + ", ".join(f"{k} {v['max_relative_difference']:.1e} ({v['pairs']} pairs)"
                            for k, v in agree.items()) + " (float32 rounding)."]
    return out + [""]


def _threads_table(results: dict) -> list:
    tp = results.get("throughput")
    out = ["## Threads", ""]
    if _failed(tp) or len(tp["threads"]) < 2:
        return out + ["No thread comparison (one CPU, no `adobe_bsdf.config`, or the "
                      "throughput section did not run).", ""]
    cpus = tp["threads"][0]
    index = {(r["case"], r["call"], r["n"], r["threads"]): r for r in tp["rows"] if "n" in r}
    sizes = [n for n in tp["sizes"] if n <= tp["reference_size"]]
    calls = [c for c in CALLS if any(r.get("call") == c for r in tp["rows"])]
    out += [f"Speed-up of {cpus} threads over 1 (time with 1 thread / time with {cpus}), "
            f"per call, at {', '.join(_n(n) for n in sizes)} pairs. \"skipped\": the "
            "1-thread run did not fit in the time budget. A lobe that does not declare scalar "
            "parameters (`Lobe._param_shape`) runs unchunked on the calling thread: speed-up "
            "~1.", "",
            "| case | n | " + " | ".join(calls) + " |", "|---|---|" + "---|" * len(calls)]
    for case in dict.fromkeys(r["case"] for r in tp["rows"]):
        for n in sizes:
            cells = []
            for c in calls:
                one, all_ = index.get((case, c, n, 1)), index.get((case, c, n, cpus))
                if one and all_ and "seconds" in one and "seconds" in all_:
                    cells.append(f"{one['seconds'] / all_['seconds']:.2f}")
                else:
                    cells.append("skipped" if one and "skipped" in one else "–")
            out.append(f"| {case} | {_n(n)} | " + " | ".join(cells) + " |")
    return out + [""]


def _throughput(results: dict, figure: str | None) -> list:
    tp = results.get("throughput")
    out, missing = _opening("Throughput of every registered case", "Throughput", tp)
    if missing:
        return missing
    cpus = tp["threads"][0]
    index = {(r["case"], r["call"], r["n"], r["threads"]): r for r in tp["rows"] if "n" in r}
    calls = [c for c in CALLS if any(r.get("call") == c for r in tp["rows"])]
    skipped = [r for r in tp["rows"] if "skipped" in r]
    errors = [r for r in tp["rows"] if "error" in r]
    out += [f"Evaluations per second with {_threads(cpus)} threads (memory passes in "
            f"parentheses), median of {tp['runs']} runs, `adobe_bsdf.validation.cases.cases()`. "
            f"Sizes above {_n(tp['slice'])} are run in slices of {_n(tp['slice'])}. Every "
            f"case is measured at the sizes up to {_n(tp['reference_size'])}; the 1-thread "
            f"runs at {_n(tp['reference_size'])} and the larger sizes are run cheapest first "
            f"(predicted from the {_n(tp['reference_size'])} time) within a budget of "
            f"{tp['extra_seconds']} s: {_time(tp['phase2_seconds'])} spent, {len(skipped)} "
            f"measurements skipped (phase 1 took {_time(tp['phase1_seconds'])}).", ""]
    if figure:
        out += [f"![throughput]({figure})", ""]
    for n in tp["sizes"]:
        out += [f"### {_n(n)} pairs (one memory pass: "
                f"{_time(tp['memory_pass_seconds'][str(n)])})", ""]
        if n > tp["slice"]:
            out += [f"(The lobes run on slices of {_n(tp['slice'])} pairs, the `np.add` of "
                    "the memory pass on whole arrays, which costs more per element here: "
                    "fewer passes than at 10^6 need not mean a faster lobe.)", ""]
        out += ["| case | " + " | ".join(calls) + " |", "|---|" + "---|" * len(calls)]
        for case in dict.fromkeys(r["case"] for r in tp["rows"]):
            out.append(f"| {case} | "
                       + " | ".join(_cell(index.get((case, c, n, cpus))) for c in calls) + " |")
        out.append("")
    if skipped:
        out += [f"<details><summary>{len(skipped)} measurements skipped (time budget)"
                "</summary>", "", "| case | call | n | threads | predicted time |",
                "|---|---|---|---|---|"]
        out += [f"| {r['case']} | {r['call']} | {_n(r['n'])} | {_threads(r['threads'])} | "
                f"{r['predicted_seconds']:.0f} s |"
                for r in sorted(skipped, key=lambda r: r["predicted_seconds"])]
        out += ["", "</details>", ""]
    if errors:
        out += ["Errors: " + "; ".join(f"{r.get('case')} {r.get('call', '')}: {r['error']}"
                                       for r in errors), ""]
    return out


def _active(results: dict, figure: str | None) -> list:
    al = results.get("active_lobes")
    out, missing = _opening("Cost against the number of active lobes", "Active-lobes", al)
    if missing:
        return missing
    out += [f"`Sum(*components, weights=w)` of K = {al['K']} lobes "
            f"({', '.join(al['components'])}), the first k with weight 1/k and the others "
            f"exactly 0.0, on {_n(al['n'])} pairs, all threads, median of {al['runs']} runs. "
            "*Plain Sum*: `Sum(*active)` without the zero-weight components.", ""]
    if al["api"] != "weights":
        out += ["**`Sum` has no `weights` keyword in this commit**: every row is the plain "
                "`Sum(*active)` (no row for k = 0).", ""]
    if figure:
        out += [f"![active lobes]({figure})", ""]
    out += ["| k | active | eval | sample | plain Sum eval | eval passes |",
            "|---|---|---|---|---|---|"]
    for r in al["rows"]:
        if "eval" not in r:
            why = r.get("skipped") or r.get("error", "")
            out.append(f"| {r['k']} | {', '.join(r['active']) or '–'} | {why} | | | |")
            continue
        plain = r.get("plain_eval", {}).get("seconds")
        out.append(f"| {r['k']} | {', '.join(r['active']) or 'none'} | "
                   f"{_time(r['eval']['seconds'])} | {_time(r['sample']['seconds'])} | "
                   f"{_time(plain)} | {r['eval']['seconds'] / al['memory_pass_seconds']:.0f} |")
    return out + [""]


def _materials(results: dict, figure_dir: Path, link_prefix: str, smoke: bool) -> list:
    section = results.get("materials")
    out, missing = _opening("Whole materials against their lobes", "Materials", section)
    if missing:
        return missing
    from benchmarks import material_cost

    figure_dir.mkdir(parents=True, exist_ok=True)
    return [material_cost.markdown(section, figure_dir, smoke, link_prefix)]


def _tradeoff(results: dict, figure_dir: Path, smoke: bool) -> list:
    section = results.get("tradeoff")
    if section is None or "error" in section and "settings" not in section:
        why = section["error"].strip().splitlines()[-1] if section else "module not importable"
        return ["## Speed versus accuracy", "", f"tradeoff section not available ({why}).", ""]
    try:
        from benchmarks import tradeoff

        return [tradeoff.markdown(section, figure_dir, smoke)]
    except Exception as exc:  # its rendering failing must not lose the rest
        return ["## Speed versus accuracy", "",
                f"tradeoff section not available (rendering failed: {type(exc).__name__}: "
                f"{exc}).", ""]


def merged(results: dict) -> dict:
    """``results`` of some sections over the existing ``RESULTS`` file: its other sections
    kept, each section's date recorded (``measured``)."""
    if not RESULTS.exists():
        return results
    old = json.loads(RESULTS.read_text(encoding="utf-8"))
    date = results["machine"]["date_utc"]
    out = dict(old)
    out["measured"] = {**{k: old["machine"]["date_utc"] for k in old.get("sections", [])},
                       **old.get("measured", {}), **{k: date for k in results["sections"]}}
    for key in results["sections"]:
        out[key] = results[key]
    out["sections"] = list(dict.fromkeys(old.get("sections", []) + results["sections"]))
    out["section_seconds"] = {**old.get("section_seconds", {}),
                              **results["section_seconds"]}
    return out


def _conformance(results: dict) -> list:
    section = results.get("conformance")
    out, missing = _opening("Conformance: the time of a verdict", "Conformance", section)
    if missing:
        return missing
    when = results.get("measured", {}).get("conformance")
    out += ["`conformance.compare` judging a candidate against its reference, the default "
            "views, one run each" + (f" (measured {when})" if when else "") + "; "
            "`python -m benchmarks.conformance_cost` writes the same table to "
            "[conformance_measured.md](conformance_measured.md).", "",
            "| candidate | samples per view | views | seconds | verdict |",
            "|---|---|---|---|---|"]
    for label, n, views, t, passed in section["rows"]:
        out.append(f"| {label} | {n} | {views} | {t:.1f} | "
                   f"{'conforms' if passed else 'does not conform'} |")
    return out + [""]


def markdown(results: dict, figure_dir: Path, link_prefix: str, smoke: bool) -> str:
    """The whole ``performance.md``; writes its figures into ``figure_dir``."""
    plt = pyplot()
    figures = {}
    if plt is not None:
        figure_dir.mkdir(parents=True, exist_ok=True)
        for name, plot, key in (("performance_throughput.png", _plot_throughput, "throughput"),
                                ("performance_active_lobes.png", _plot_active, "active_lobes")):
            section = results.get(key)
            if section and not _failed(section) and plot(plt, section, figure_dir / name):
                figures[key] = f"{link_prefix}{name}"
    out = _header(results, plt is not None)
    out += _headline(results) + _before_after(results) + _mitsuba(results)
    out += _threads_table(results) + _chunks(results)
    out += _throughput(results, figures.get("throughput"))
    out += _active(results, figures.get("active_lobes"))
    out += _materials(results, figure_dir, link_prefix, smoke)
    out += _tradeoff(results, figure_dir, smoke)
    out += _conformance(results)
    return "\n".join(out).rstrip() + "\n"


def write(results: dict, out: Path | None, smoke: bool) -> dict:
    """Write results.json, performance.md and the figures; returns their paths."""
    if out is None:
        json_path, md_path, figure_dir = RESULTS, DOCS / "performance.md", DOCS / "figures"
    else:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        json_path, md_path, figure_dir = out / "results.json", out / "performance.md", \
            out / "figures"
    json_path.write_text(json.dumps(_clean(results), indent=1) + "\n", encoding="utf-8")
    md_path.write_text(markdown(results, figure_dir, "figures/", smoke), encoding="utf-8")
    return {"json": json_path, "markdown": md_path, "figures": figure_dir}


def main(argv=None) -> None:
    """``python -m benchmarks.report [RESULTS_JSON]``: rewrite ``docs/performance.md`` and
    its figures from a results file (default ``benchmarks/results.json``) without measuring
    again."""
    import argparse

    parser = argparse.ArgumentParser(description=main.__doc__.splitlines()[0])
    parser.add_argument("results", nargs="?", type=Path, default=RESULTS)
    args = parser.parse_args(argv)
    results = json.loads(args.results.read_text(encoding="utf-8"))
    DOCS.joinpath("performance.md").write_text(
        markdown(results, DOCS / "figures", "figures/", results.get("smoke", False)),
        encoding="utf-8")


if __name__ == "__main__":
    main()
