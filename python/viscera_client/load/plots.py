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


def round_trip_histograms(report, path, round_trips):
    """One histogram of pose->force round trips (ms) per session. `round_trips`:
    session_id -> list of us."""
    sessions = report["sessions"]
    n = len(sessions)
    if n <= MAX_PANELS:
        cols = min(4, n)
        rows = (n + cols - 1) // cols
        fig, axes = plt.subplots(rows, cols, figsize=(3.2 * cols, 2.4 * rows), squeeze=False,
                                 sharex=True)
        for ax in axes.flat[n:]:
            ax.set_visible(False)
        for ax, s in zip(axes.flat, sessions):
            values = [v / 1000.0 for v in round_trips.get(s["session_id"], [])]
            ax.hist(values, bins=40, color="tab:blue")
            rt = s["round_trip_us"]
            if rt["p99"] is not None:
                ax.axvline(rt["p99"] / 1000.0, color="tab:red", lw=1, label="p99")
            ax.set_title(f"{s['session_id'] % 100000} on {s['server']}", fontsize=8)
            ax.tick_params(labelsize=7)
        for ax in axes[-1]:
            ax.set_xlabel("round trip (ms)", fontsize=8)
    else:
        fig, ax = plt.subplots(figsize=(7, 4))
        for s in sessions:
            values = [v / 1000.0 for v in round_trips.get(s["session_id"], [])]
            ax.hist(values, bins=60, histtype="step", lw=0.8)
        ax.set_xlabel("round trip (ms)")
        ax.set_ylabel("poses")
    fig.suptitle(f"pose -> force round trip per session ({_label(report)})", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def rates_over_time(report, path):
    """Achieved mechanics rate (server status) and pose rate (client), and cumulative
    deadline misses, per session over the run."""
    fig, (ax_rate, ax_miss) = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
    for s in report["sessions"]:
        st = s["status_timeline"]
        label = f"{s['session_id'] % 100000}"
        if st:
            ax_rate.plot([p["t"] for p in st], [p["achieved_rate_hz"] for p in st], lw=1,
                         label=label)
            ax_miss.step([p["t"] for p in st], [p["deadline_misses"] for p in st], where="post",
                         lw=1)
        tl = s["timeline"]
        ax_rate.plot([p["t"] + 0.5 for p in tl], [p["poses"] for p in tl], ls=":", lw=0.8,
                     color="gray")
    ax_rate.set_ylabel("rate (Hz)\nmechanics, poses dotted")
    ax_miss.set_ylabel("deadline misses\n(cumulative)")
    ax_miss.set_xlabel("time since start (s)")
    if len(report["sessions"]) <= 12:
        ax_rate.legend(fontsize=7, ncol=4, title="session", title_fontsize=7)
    fig.suptitle(_label(report), fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def capacity_curve(reports, path, title=""):
    """Deadline-miss share and round-trip p99 against sessions, over several runs; the
    limits (0.1 % of steps, one mechanics period) drawn as dashed lines."""
    reports = sorted(reports, key=lambda r: r["overall"]["sessions"])
    n = [r["overall"]["sessions"] for r in reports]
    misses = [100.0 * (r["overall"]["miss_fraction"] or 0.0) for r in reports]
    p99 = [(r["overall"]["round_trip_us"]["p99"] or 0.0) / 1000.0 for r in reports]
    rate = reports[0]["sessions"][0]["rate_hz"] if reports and reports[0]["sessions"] else 0
    fig, ax = plt.subplots(figsize=(6.5, 4))
    ax.plot(n, misses, "o-", color="tab:red", label="deadline misses (% of steps)")
    ax.axhline(0.1, color="tab:red", ls="--", lw=0.8)
    ax.set_xlabel("sessions")
    ax.set_ylabel("deadline misses (%)", color="tab:red")
    ax2 = ax.twinx()
    ax2.plot(n, p99, "s-", color="tab:blue", label="round trip p99 (ms)")
    if rate:  # the round-trip limit: two periods (report.py says why)
        ax2.axhline(2000.0 / rate, color="tab:blue", ls="--", lw=0.8)
    ax2.set_ylabel("round trip p99 (ms)", color="tab:blue")
    for r, x, y in zip(reports, n, p99):
        if not r["overall"]["client_ok"]:
            ax2.annotate("client slow", (x, y), fontsize=7)
    ax.set_title(title or "capacity", fontsize=9)
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
        capacity_curve(reports, p, f"scene {a['scene']}, mechanics {a['session_rate_hz'] or 'scene'} Hz,"
                       f" poses {a['pose_rate_hz']:g} Hz" + (", frames" if a["frames"] else ""))
        paths.append(p)
    return paths
