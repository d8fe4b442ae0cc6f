#!/usr/bin/env python3
"""Fails on words that describe how the people working on viscera work, not viscera itself.

Usage: tools/check_words.py              checks every tracked text file; prints file:line and exits 1
                                         on a hit
       tools/check_words.py --self-test  checks the patterns against their own examples
       tools/check_words.py FILE...      checks these files (tracked or not); - reads standard
                                         input (git log --format=%B main.. | tools/check_words.py -)

The repository speaks of the project only: what the code does, why, and what was measured. Work
periods, the people and their roles, code reviews, version-control branches, ticket numbers and
notes kept outside the repository mean nothing to a reader of the tree, and go stale at once.

WORDS below is the only list. Each entry: a category, a regular expression, examples it must catch,
and product phrases it must leave alone (the self-test, run by tools/test.sh, checks both, so a
pattern that stops catching, or starts catching the product, fails). The patterns are calibrated on
the tree: "session" is a product word (a server runs sessions), so only a session with a number in
prose is flagged; write a session id in backticks or quotes, as the product's messages appear
(`session 42`). "helper" (a helper thread, a helper function), "branch" (branch-free code) and
"review" stay legal in their ordinary meanings. This file is not checked: it holds the list.
"""

import re
import subprocess
import sys
from pathlib import Path

# (category, pattern, must catch, must not catch)
WORDS = [
    # A numbered session is a work period; a product session id is written in quotes or backticks,
    # which are removed before this category is matched (see QUOTED). A figure after it
    # ("a 1 kHz session 5 % of its deadlines") is not an id.
    ("work period", r"\b[Ss]ession[- ]#?[0-9]+\b(?!\s*%)",
     ["measured in session 8", "Session 12's figures", "the session-9 run", "(session 10)"],
     ["receiver.find(\"session 8\")", "`no tool 'Right' in session 42`",
      "a 1 kHz session 5 % of its deadlines", "sessions at 100 Hz", "session's 3 tools"]),
    ("people", r"\bsub-?agents?\b|(?<!user )(?<!user-)(?<!User-)\bagents?\b",
     ["a subagent measured it", "the agent's notes"],
     ["User-Agent: curl/7.88", "the user agent string"]),
    ("people", r"\bhelpers?(?:'s|')? (?:reports?|sessions?|runs?|notes|findings|figures|numbers"
     r"|measurements?|worktrees?|commits?|work)\b"
     r"|\b(?:a|the|another|each|one|my|our|second) helper (?:found|wrote|measured|ran|said"
     r"|reported|fixed|added|asked|tried|checked|saw|did|made|noted)\b",
     ["the helper's figures", "a helper measured 3 ms", "helper report"],
     ["a helper thread does the build", "the helper's exception arrives", "one helper for both",
      "the helper abandons the build", "Helpers for end-to-end tests"]),
    ("people", r"\b[Tt]he lead(?:'s)?\b|\blead (?:engineer|developer)s?\b",
     ["the lead's session figures", "as the lead asked"],
     ["the leading contacts", "lead time"]),
    ("code review", r"\b[Rr]eviewers?\b|\b[Tt]he review(?:'s|s)?\b"
     r"|\b[Rr]eview (?:[0-9]+|mends?|fix(?:es)?|comments?|notes?|findings?|asked|found|said|round)\b"
     r"|\b(?:code|final|last|first|second|third|peer|this|that) review\b"
     r"|\b(?:after|before|per|in|from|for|under) review\b",
     ["after the review's mend", "Review mends: one penalty", "the final review", "a reviewer"],
     ["the trainee reviews the record"]),
    ("version control", r"\b(?:git|feature|topic|work(?:ing)?|main|master|staging|release|(?:un)?merged"
     r"|my|our|their|its own|a new|the other) branch(?:es)?\b"
     r"|\b[Bb]ranch ['`\"][A-Za-z0-9._/-]+['`\"]"
     r"|\b(?:merg(?:e|ed|es|ing)|rebas(?:e|ed|ing)|check(?:ed)? ?out|push(?:ed)?) (?:of |into |onto |from |"
     r"the |this |a |my |our )*branch"
     r"|\b[Mm]erg(?:e|ed|es|ing) (?:it |them |this )?(?:in)?to (?:main|master|staging)\b"
     r"|\bworktrees?\b",
     ["Merge branch 'cost8'", "on the feature branch", "merged into main", "git worktree add"],
     ["branch-free without roots", "branching vessels", "both sides of a branch on a uniform",
      "the normal branch", "the paused branch of the summary"]),
    ("ticket", r"\b(?:[Ii]ssues?|[Tt]ickets?|[Bb]ugs?|PRs?|[Pp]ull requests?) #?[0-9]+\b"
     r"|\b(?:TODO|FIXME|XXX)\([^)]*\)",
     ["where issue 10 stands", "issue #12's test", "TODO(alex): later", "PR 7"],
     ["tissue 10 mm away", "the bug in 3 of 5 runs"]),
    ("outside file", r"\.\./shared\b|(?<![A-Za-z0-9_./-])shared/[A-Za-z]|(?<![A-Za-z0-9_./-])/(?:work|home)/",
     ["see ../shared/notes.md", "shared/reviews/8.md", "in /work/main/build"],
     ["../proto/*.lcm", "$here/../..", "/tmp/fall.jsonl", "lib/shared/x"]),
]

# Upper-case Markdown names (DESIGN.md, NOTES.md) must be files of the repository.
OUTSIDE_MD = re.compile(r"\b[A-Z][A-Z0-9_-]*\.md\b")

# Product strings: a session id inside "..." or `...` is an id, not a work period.
QUOTED = re.compile(r'"[^"\n]*"|`[^`\n]*`')

COMPILED = [(cat, re.compile(p)) for cat, p, _, _ in WORDS]


def hits(line, tracked_md=frozenset()):
    """Yields (category, matched text) for each pattern that matches LINE."""
    unquoted = QUOTED.sub('""', line)
    for cat, rx in COMPILED:
        m = rx.search(unquoted if cat == "work period" else line)
        if m:
            yield cat, m.group(0)
    for m in OUTSIDE_MD.finditer(line):
        if m.group(0) not in tracked_md:
            yield "outside file", m.group(0)


def self_test():
    failures = 0
    for (cat, _, catch, leave), (_, rx) in zip(WORDS, COMPILED):
        for text in catch:
            if not any(c == cat for c, _ in hits(text)):
                print(f"check_words: [{cat}] does not catch: {text}", file=sys.stderr)
                failures += 1
        for text in leave:
            found = list(hits(text, frozenset({"README.md"})))
            if found:
                print(f"check_words: [{cat}] catches product text: {text} ({found})", file=sys.stderr)
                failures += 1
    if not list(hits("see DESIGN.md", frozenset({"README.md"}))):
        print("check_words: an untracked DESIGN.md is not caught", file=sys.stderr)
        failures += 1
    print(f"check_words: self-test, {len(WORDS)} patterns, {failures} failure(s)", file=sys.stderr)
    return 1 if failures else 0


def main(argv):
    root = Path(__file__).resolve().parent.parent
    if argv[1:] == ["--self-test"]:
        return self_test()
    tracked = subprocess.run(["git", "-C", str(root), "ls-files", "-z"], check=True,
                             capture_output=True).stdout.decode().split("\0")
    tracked = [t for t in tracked if t]
    tracked_md = frozenset(Path(t).name for t in tracked if t.endswith(".md"))
    this = Path(__file__).resolve()
    files = argv[1:] or tracked
    found = 0
    for name in files:
        path = Path(name) if argv[1:] else root / name
        if name == "-":
            data = sys.stdin.buffer.read()
        elif path.resolve() == this or not path.is_file():
            continue
        else:
            data = path.read_bytes()
        if b"\0" in data[:8192]:
            continue  # binary (pictures)
        for number, line in enumerate(data.decode("utf-8", "replace").splitlines(), 1):
            for cat, text in hits(line, tracked_md):
                print(f"{name}:{number}: [{cat}] \"{text}\": {line.strip()[:160]}")
                found += 1
    if found:
        print(f"check_words: {found} line(s) speak of how the work is done, not of viscera "
              "(tools/check_words.py lists the words and why)", file=sys.stderr)
        return 1
    print(f"check_words: {len(files)} files, none speaks of the process", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
