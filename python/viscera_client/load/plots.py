"""PNG plots of load-test reports (matplotlib, Agg: no display needed)."""
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

MAX_PANELS = 16  # more sessions than this: one overlaid histogram instead of small multiples


def _label(report):
    a = report["overall"]["settings"]
    return (f"{report['overall']['sessions']} sessions, scene {a['scene']}, "
            f"{a['pose_rate_hz']:g} Hz poses" + (", frames" if a["frames"] else ""))


def session_label(s):
    """A session as the report names it: its full id and its server."""
    return f"{s['session_id']} on {s['server']}"


def _limit_us(report):
    limits = [s["round_trip_limit_us"] for s in report["sessions"] if s["round_trip_limit_us"]]
    return max(limits) if limits else None


def _percentile_lines(ax, rt, limit_us):
    """p50, p95, p99 and the round-trip limit as labeled vertical lines (ms)."""
    for key, color, style in (("p50", "tab:green", "-"), ("p95", "tab:orange", "-"),
                              ("p99", "tab:red", "-")):
        if rt[key] is not None:
            ax.axvline(rt[key] / 1000.0, color=color, ls=style, lw=1,
                       label=f"{key} {rt[key] / 1000.0:.2f} ms")
    if limit_us:
        ax.axvline(limit_us / 1000.0, color="black", ls="--", lw=1,
                   label=f"limit {limit_us / 1000.0:.0f} ms (2 periods)")


def round_trip_histograms(report, path, round_trips):
    """One histogram of pose->force round trips (ms) per session, with its p50, p95, p99
    and the round-trip limit labeled. `round_trips`: session_id -> list of us."""
    sessions = report["sessions"]
    n = len(sessions)
    limit_us = _limit_us(report)
    if n <= MAX_PANELS:
        cols = min(3, n)
        rows = (n + cols - 1) // cols
        fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 2.9 * rows), squeeze=False,
                                 sharex=True)
        for ax in axes.flat[n:]:
            ax.set_visible(False)
        for ax, s in zip(axes.flat, sessions):
            values = [v / 1000.0 for v in round_trips.get(s["session_id"], [])]
            ax.hist(values, bins=40, color="tab:blue")
            _percentile_lines(ax, s["round_trip_us"], limit_us)
            ax.set_title(session_label(s), fontsize=8)
            ax.set_xlim(left=0.0)
            ax.set_ylabel("poses", fontsize=8)
            ax.tick_params(labelsize=7)
            ax.legend(fontsize=6)
        for ax in axes[-1]:
            ax.set_xlabel("round trip (ms)", fontsize=8)
    else:
        fig, ax = plt.subplots(figsize=(7, 4))
        for s in sessions:
            values = [v / 1000.0 for v in round_trips.get(s["session_id"], [])]
            ax.hist(values, bins=60, histtype="step", lw=0.8)
        _percentile_lines(ax, report["overall"]["round_trip_us"], limit_us)
        ax.set_xlim(left=0.0)
        ax.legend(fontsize=7, title="all sessions pooled", title_fontsize=7)
        ax.set_xlabel("round trip (ms)")
        ax.set_ylabel("poses")
    fig.suptitle(f"pose -> force round trip per session ({_label(report)})", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def rates_over_time(report, path):
    """Achieved mechanics rate (server status) and pose rate (client), and cumulative
    deadline misses against the 0.1 % limit, per session over the run (legend: full session
    ids and their servers; the same ids as the JSON report)."""
    fig, (ax_rate, ax_miss) = plt.subplots(2, 1, figsize=(8.5, 6), sharex=True)
    rates = set()
    for s in report["sessions"]:
        st = s["status_timeline"]
        rates.add(s["rate_hz"])
        if st:
            line, = ax_rate.plot([p["t"] for p in st], [p["achieved_rate_hz"] for p in st], lw=1,
                                 label=session_label(s))
            ax_miss.step([p["t"] for p in st], [p["deadline_misses"] for p in st], where="post",
                         lw=1, color=line.get_color())
        tl = s["timeline"]
        ax_rate.plot([p["t"] + 0.5 for p in tl], [p["poses"] for p in tl], ls=":", lw=0.8,
                     color="gray")
    top = max(list(rates) + [report["overall"]["settings"]["pose_rate_hz"]]) or 1.0
    for rate in rates:
        ax_rate.axhline(rate, color="black", ls="--", lw=0.8)
    # rates from zero: a 0.3 Hz wobble is not a collapse
    ax_rate.set_ylim(0.0, 1.2 * top)
    seconds = report["overall"]["settings"]["seconds"]
    ax_rate.set_xlim(0.0, seconds)
    steps_per_s = sum(rates) / len(rates) if rates else 0.0
    if steps_per_s:
        ax_miss.plot([0.0, seconds], [0.0, 0.001 * steps_per_s * seconds], color="black", ls="--",
                     lw=0.8, label="0.1 % of one session's steps")
        ax_miss.legend(fontsize=7, loc="upper left")
    ax_miss.set_ylim(bottom=0.0)
    ax_rate.set_ylabel("rate (Hz)\nmechanics; poses dotted;\nasked rate dashed", fontsize=8)
    ax_miss.set_ylabel("deadline misses\n(cumulative)", fontsize=8)
    ax_miss.set_xlabel("time since the measurement began (s)")
    if len(report["sessions"]) <= 12:
        ax_rate.legend(fontsize=7, ncol=2, title="session", title_fontsize=7, loc="lower right")
    fig.suptitle(_label(report), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def per_server(reports):
    """{server: [(sessions on it, miss %, round-trip p99 ms, client ok), ...]} over runs."""
    out = {}
    for r in reports:
        by_server = {}
        for s in r["sessions"]:
            by_server.setdefault(s["server"], []).append(s)
        for server, sessions in by_server.items():
            steps = sum(s["mechanics"]["steps"] for s in sessions)
            misses = sum(s["mechanics"]["deadline_misses"] for s in sessions)
            p99 = max((s["round_trip_us"]["p99"] or 0.0) for s in sessions) / 1000.0
            out.setdefault(server, []).append(
                (len(sessions), 100.0 * misses / steps if steps else 0.0, p99,
                 r["overall"]["client_ok"]))
    return {k: sorted(v) for k, v in out.items()}


def capacity_curve(reports, path, title=""):
    """Per server: deadline-miss share and the worst session's round-trip p99 against the
    sessions it held, over several runs; the limits (0.1 % of steps, two mechanics periods)
    dashed. Whole sessions on the x axis."""
    from matplotlib.ticker import MaxNLocator
    curves = per_server(reports)
    rate = next((s["rate_hz"] for r in reports for s in r["sessions"]), 0)
    fig, (ax_miss, ax_rt) = plt.subplots(1, 2, figsize=(10, 4))
    for server, points in sorted(curves.items()):
        n = [p[0] for p in points]
        ax_miss.plot(n, [p[1] for p in points], "o-", label=server)
        ax_rt.plot(n, [p[2] for p in points], "s-", label=server)
        for x, _, y, client_ok in points:
            if not client_ok:
                ax_rt.annotate("client slow", (x, y), fontsize=7)
    ax_miss.axhline(0.1, color="black", ls="--", lw=0.8, label="limit 0.1 %")
    if rate:  # the round-trip limit: two periods (report.py says why)
        ax_rt.axhline(2000.0 / rate, color="black", ls="--", lw=0.8,
                      label=f"limit {2000.0 / rate:.0f} ms (2 periods)")
    for ax in (ax_miss, ax_rt):
        ax.set_xlabel("sessions on the server")
        ax.xaxis.set_major_locator(MaxNLocator(integer=True))
        ax.set_ylim(bottom=0.0)
        ax.legend(fontsize=7, title="server", title_fontsize=7)
    ax_miss.set_ylabel("deadline misses (% of steps)")
    ax_rt.set_ylabel("round trip p99, worst session (ms)")
    fig.suptitle(title or "capacity per server", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_plots(directory, reports, round_trips, prefix=""):
    """The PNGs of one or several runs into `directory`; returns their paths."""
    os.makedirs(directory, exist_ok=True)
    paths = []
    for r in reports:
        tag = f"{prefix}n{r['overall']['sessions']}"
        p = os.path.join(directory, f"{tag}_round_trip.png")
        round_trip_histograms(r, p, round_trips)
        paths.append(p)
        p = os.path.join(directory, f"{tag}_rates.png")
        rates_over_time(r, p)
        paths.append(p)
    if len(reports) > 1:
        p = os.path.join(directory, f"{prefix}capacity.png")
        a = reports[0]["overall"]["settings"]
        mechanics = (f"mechanics at {a['session_rate_hz']:g} Hz" if a["session_rate_hz"]
                     else "mechanics at the scene's rate")
        capacity_curve(reports, p, f"capacity per server: scene {a['scene']}, {mechanics}, "
                       f"poses {a['pose_rate_hz']:g} Hz" + (", frames" if a["frames"] else ""))
        paths.append(p)
    return paths
