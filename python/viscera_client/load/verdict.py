"""Whether a run's deadline misses put a server over its 0.1 % limit, and whether the run
could tell at all. Pure Python: no LCM, no numpy.

Misses are rare events: k misses in n steps is a Poisson count of mean p * n for a true miss
share p. A run says "over" only when k is unlikely (below 5 %) if p were at the limit, and
"within" only when p at the limit would likely (95 %) have given more than k; between the
two it cannot resolve the limit, and says how many steps would.

Misses that hit most sessions in the same second are host stalls (the machine paused every
thread at once: another process, the tester's own start-up), not a server short of cores;
they are counted apart while they stay rare (at most MAX_STALL_SHARE of the run's seconds).
"""
import math

MAX_MISS_FRACTION = 0.001
CONFIDENCE = 0.95
# a second in which at least this share of the sessions (and at least two) missed
STALL_SESSION_SHARE = 0.5
# stalls that fill more of the run than this are no longer stalls: the machine is overloaded
MAX_STALL_SHARE = 0.1


def poisson_cdf(k, lam):
    """P(X <= k) for X ~ Poisson(lam): summed in log space up to lam 200, the normal
    approximation (continuity corrected) above, so that a long run's thousands of steps cost
    no more than a short one's."""
    if k < 0:
        return 0.0
    if lam <= 0.0:
        return 1.0
    if lam > 200.0:
        return 0.5 * math.erfc(-(k + 0.5 - lam) / math.sqrt(2.0 * lam))
    k = int(k)
    if k > lam + 40.0 * math.sqrt(lam) + 40.0:
        return 1.0  # the rest of the tail is below double precision
    log_lam = math.log(lam)
    total = sum(math.exp(i * log_lam - lam - math.lgamma(i + 1)) for i in range(k + 1))
    return min(1.0, total)


def upper_bound(k, confidence=CONFIDENCE):
    """The mean lam for which P(X <= k) = 1 - confidence: the one-sided upper bound on a
    Poisson mean after k events (2.996 for k = 0 at 95 %)."""
    lo, hi = 0.0, max(10.0, 4.0 * (k + 5))
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        if poisson_cdf(k, mid) > 1.0 - confidence:
            lo = mid
        else:
            hi = mid
    return hi


def miss_verdict(misses, steps, limit=MAX_MISS_FRACTION, confidence=CONFIDENCE):
    """{"verdict": "within" | "over" | "unresolved" | "no steps", "misses", "steps",
    "fraction", "upper_fraction" (the share this run cannot exclude, at `confidence`),
    "steps_to_resolve" (steps at this share that would decide; None when decided or at the
    limit itself), "text"}."""
    out = {"misses": misses, "steps": steps, "limit_fraction": limit, "confidence": confidence,
           "fraction": None, "upper_fraction": None, "steps_to_resolve": None}
    if steps <= 0:
        out.update(verdict="no steps", text="no steps observed")
        return out
    fraction = misses / steps
    out["fraction"] = fraction
    out["upper_fraction"] = upper_bound(misses, confidence) / steps
    expected_at_limit = limit * steps
    if misses > 0 and 1.0 - poisson_cdf(misses - 1, expected_at_limit) < 1.0 - confidence:
        verdict = "over"
    elif out["upper_fraction"] < limit:
        verdict = "within"
    else:
        verdict = "unresolved"
        out["steps_to_resolve"] = steps_to_resolve(fraction, steps, limit, confidence)
    out["verdict"] = verdict
    share = f"{misses} deadline miss{'es' if misses != 1 else ''} in {steps} steps " \
            f"({100 * fraction:.3f} %)"
    if verdict == "over":
        out["text"] = f"{share}: above the {100 * limit:g} % limit"
    elif verdict == "within":
        out["text"] = (f"{share}: within the {100 * limit:g} % limit (at most "
                       f"{100 * out['upper_fraction']:.3f} % at {100 * confidence:g} %)")
    else:
        more = out["steps_to_resolve"]
        out["text"] = (f"{share}: this run cannot tell against the {100 * limit:g} % limit "
                       f"(it cannot exclude {100 * out['upper_fraction']:.3f} %); "
                       + (f"about {more} steps would resolve it: repeat, or run longer"
                          if more else "the share sits at the limit itself"))
    return out


def steps_to_resolve(fraction, steps, limit=MAX_MISS_FRACTION, confidence=CONFIDENCE):
    """Steps after which a run missing `fraction` of them would be decided either way (the
    smallest multiple of 1.25 of `steps` that does), or None at the limit itself."""
    if abs(fraction - limit) < 1e-12:
        return None
    n = float(steps)
    while n < 1e6 * max(steps, 1):  # beyond a million times the run: say nothing
        n *= 1.25
        k = round(fraction * n)
        if fraction < limit and upper_bound(k, confidence) / n < limit:
            return int(math.ceil(n))
        if fraction > limit and 1.0 - poisson_cdf(k - 1, limit * n) < 1.0 - confidence:
            return int(math.ceil(n))
    return None


def host_stalls(sessions):
    """Seconds of the run in which most sessions missed a deadline at once. `sessions`:
    session reports (their status_timeline: t in s, cumulative deadline_misses). Returns
    {"seconds": [t, ...], "misses": misses in those seconds, "by_second": {t: {session_id:
    misses}}}; with one session nothing can coincide: no stalls."""
    by_second = {}
    for s in sessions:
        previous = 0
        for point in s["status_timeline"]:
            new = point["deadline_misses"] - previous
            previous = point["deadline_misses"]
            if new > 0:
                second = int(math.floor(point["t"]))
                by_second.setdefault(second, {})
                by_second[second][s["session_id"]] = by_second[second].get(s["session_id"], 0) + new
    n = len(sessions)
    stalls = sorted(t for t, hit in by_second.items()
                    if n >= 2 and len(hit) >= 2 and len(hit) >= STALL_SESSION_SHARE * n)
    return {"seconds": stalls, "misses": sum(sum(by_second[t].values()) for t in stalls),
            "by_second": {t: by_second[t] for t in stalls}}


def judged_misses(total_misses, stalls, run_seconds):
    """The misses a run is judged by: all of them, less those of host stalls while stalls
    stay rare (at most MAX_STALL_SHARE of the run's seconds, and at least one second may)."""
    if not stalls["seconds"]:
        return total_misses, False
    if len(stalls["seconds"]) > max(1.0, MAX_STALL_SHARE * run_seconds):
        return total_misses, False
    return max(0, total_misses - stalls["misses"]), True
