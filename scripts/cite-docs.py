#!/usr/bin/env python3
"""Citations of sections (`§N`) in the project's files, against the documents a clone holds.

The code once cited the definition the project was built from by its own numbering (the spec
file, "spec v1.4 §15", or a bare "§8.2"); a clone holds no such file. Users read the definition
in docs/SCORE.md (and the commands in docs/USAGE.md, the protocols in docs/PROTOCOLS.md, the
long tables in docs/TABLES-SCHEMA.md). This script maps each old section to the project's own.

    scripts/cite-docs.py --check     exit 1 on a citation of a document the clone lacks, or of a
                                     section a project document does not have (CI: test-all.sh)
    scripts/cite-docs.py --fix       rewrite the old citations in place (idempotent: a second
                                     run changes nothing)
    scripts/cite-docs.py --list      the citations --fix would rewrite, one a line

Citations read: `<doc>.md §N` (checked: <doc> must exist in the clone and hold a heading
numbered N), and the definition's citations: its file's name, "spec"/"definition" or a version
("v1.4") before `§N` or "section N", and a bare `§N` outside docs/SCORE.md (whose bare `§N` are
its own).
A `§N` after another document's name (a data sheet: "DDI0479C §4.3") is left alone.
"""

import argparse
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The definition's file name, spelled so that this script does not cite it.
SPEC = "SDS-" + "SPEC.md"

# Old section -> (document, section or None). A subsection not listed takes its section's entry.
MAPPING = {
    "1": ("docs/SCORE.md", "2"),
    "1.1": ("docs/SCORE.md", "2.1"),
    "1.2": ("docs/SCORE.md", "2.2"),
    "1.3": ("docs/SCORE.md", "2.3"),
    "1.4": ("docs/SCORE.md", "14.3"),
    "1.5": ("docs/SCORE.md", "14.1"),
    "2": ("docs/SCORE.md", "3"),
    "3": ("docs/SCORE.md", "4"),
    "4": ("docs/SCORE.md", "5"),
    "5": ("docs/SCORE.md", "6"),
    "6": ("docs/SCORE.md", "7"),
    "7": ("docs/SCORE.md", "8"),
    "8": ("docs/SCORE.md", "9"),
    "8.1": ("docs/SCORE.md", "10"),
    "8.2": ("docs/SCORE.md", "10.1"),
    "8.3": ("docs/SCORE.md", "10.2"),
    "8.4": ("docs/PROTOCOLS.md", None),
    "8.5": ("docs/SCORE.md", "10.0"),
    "9": ("docs/SCORE.md", "11"),
    "10": ("docs/SCORE.md", "13"),
    "10.1": ("docs/SCORE.md", "13"),
    "10.2": ("docs/SCORE.md", "14.4"),
    "10.3": ("docs/SCORE.md", "13"),
    "11": ("docs/SCORE.md", "10.3"),
    "12": ("docs/USAGE.md", "8"),
    "13": ("docs/SCORE.md", "13.2"),
    "14": ("docs/SCORE.md", "10.3"),
    "15": ("docs/TABLES-SCHEMA.md", None),
    "16": ("docs/SCORE.md", "2.4"),
    "17": ("docs/SCORE.md", "15"),
    "18": ("docs/SCORE.md", "10.4"),
}

NUM = r"[0-9]+(?:\.[0-9]+)*[a-z]?"
# The definition named before `§N`: its file (with a version), "spec"/"definition" (with a
# version), or a version alone.
# Between the name and `§N` a comment may break the line (`//!`, `///`, `#`, ` * `).
GAP = r"(?:\s+(?://[!/]?|#|\*)?\s*)"
SPEC_PREFIX = (
    r"(?:`?" + re.escape(SPEC) + r"`?(?:'s)?" + GAP + r"(?:v1\.[0-9]" + GAP + r")?"
    r"|(?:the\s+)?(?:spec|definition)(?:'s)?\s+(?:v1\.[0-9]\s+)?(?:\(\s*)?"
    r"|v1\.[0-9]\s+)"
)
SPEC_CITE = re.compile(r"(?P<prefix>" + SPEC_PREFIX + r")(?:§\s?|sections?\s+)(?P<a>" + NUM + r")(?:-(?P<b>" + NUM + r"))?")
BARE_CITE = re.compile(r"(?<![\w.`/'-])(?<![\w.`]\s)§\s?(?P<a>" + NUM + r")(?:-(?P<b>" + NUM + r"))?")
DOC_CITE = re.compile(r"(?P<doc>(?:docs/)?[A-Z][A-Z0-9_-]*\.md)`?" + GAP + r"§\s?(?P<a>" + NUM + r")(?:-(?P<b>" + NUM + r"))?")

TEXT_EXT = (".rs", ".md", ".py", ".sh", ".toml", ".h", ".c", ".cpp", ".txt", ".yml", ".yaml", ".pyi")


def tracked_files():
    out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True, check=True)
    files = [f for f in out.stdout.splitlines() if f.endswith(TEXT_EXT) or os.path.basename(f) == "run"]
    return [f for f in files if os.path.isfile(os.path.join(ROOT, f))]


def headings(doc):
    """Section numbers of a project document's headings (`## 10.`, `### 10.0a`)."""
    path = os.path.join(ROOT, doc)
    if not os.path.isfile(path):
        return None
    nums = set()
    with open(path, encoding="utf-8") as f:
        for line in f:
            m = re.match(r"#{1,6}\s+(" + NUM + r")\.?\s", line)
            if m:
                nums.add(m.group(1))
    return nums


def target(num):
    """The project's citation for an old section number, or None."""
    while num:
        if num in MAPPING:
            return MAPPING[num]
        num = num.rsplit(".", 1)[0] if "." in num else ""
    return None


def new_citation(a, b):
    ta = target(a)
    if ta is None:
        return None
    doc, sa = ta
    if sa is None:
        return doc
    if b:
        tb = target(b)
        if tb and tb[0] == doc and tb[1] and tb[1] != sa:
            return f"{doc} §{sa}-{tb[1]}"
    return f"{doc} §{sa}"


# The definition's file named without a section: the project's definition, docs/SCORE.md.
SPEC_NAMED = re.compile(r"`?" + re.escape(SPEC) + r"`?(?:\s+v1\.[0-9](?![0-9]))?")


def spec_citations(path, text):
    """(start, end, old, new, prefix) of each citation of the definition in `text`."""
    found = []
    taken = []
    for m in SPEC_CITE.finditer(text):
        found.append((m.start(), m.end(), m.group(0), new_citation(m.group("a"), m.group("b")), m.group("prefix")))
        taken.append((m.start(), m.end()))
    for m in SPEC_NAMED.finditer(text):
        if not any(s <= m.start() < e for s, e in taken):
            found.append((m.start(), m.end(), m.group(0), "docs/SCORE.md", ""))
            taken.append((m.start(), m.end()))
    if path != "docs/SCORE.md":
        for m in BARE_CITE.finditer(text):
            if any(s <= m.start() < e for s, e in taken):
                continue
            # After a document's name, on this line or the comment line before: not bare.
            before = re.sub(r"(?:\s|//[!/]?|#|\*)+$", "", text[max(0, m.start() - 80):m.start()])
            if re.search(r"\.md`?$|[A-Z0-9]{3,}$", before):
                continue
            found.append((m.start(), m.end(), m.group(0), new_citation(m.group("a"), m.group("b")), ""))
    return sorted(found)


def rewrite(path, new, prefix):
    """The new citation, keeping an opening parenthesis the old prefix held; inside docs/ a
    sibling document is named without the folder."""
    lead = "(" if prefix.rstrip().endswith("(") else ""
    if path.startswith("docs/") and new.startswith("docs/"):
        new = new[len("docs/"):]
    # A citation broken over two comment lines stays on two: the name, then the leader and `§`.
    if "\n" in prefix and " §" in new:
        doc, sec = new.split(" §", 1)
        gap = re.sub(r"v1\.[0-9]\s*", "", prefix[prefix.index("\n"):]).rstrip("( ") + " "
        return lead + doc + gap + "§" + sec
    return lead + new


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    g = ap.add_mutually_exclusive_group(required=True)
    g.add_argument("--check", action="store_true")
    g.add_argument("--fix", action="store_true")
    g.add_argument("--list", action="store_true")
    a = ap.parse_args()
    me = os.path.relpath(os.path.abspath(__file__), ROOT)
    problems, changed = [], 0
    heads = {}
    for path in tracked_files():
        if path == me:
            continue
        with open(os.path.join(ROOT, path), encoding="utf-8", errors="replace") as f:
            text = f.read()
        cites = spec_citations(path, text)
        line_of = lambda pos: text.count("\n", 0, pos) + 1
        if a.fix and cites:
            out, last = [], 0
            for s, e, old, new, prefix in cites:
                if new is None:
                    continue
                out.append(text[last:s])
                out.append(rewrite(path, new, prefix))
                last = e
            out.append(text[last:])
            new_text = "".join(out)
            if new_text != text:
                with open(os.path.join(ROOT, path), "w", encoding="utf-8") as f:
                    f.write(new_text)
                changed += 1
                text = new_text
                cites = spec_citations(path, text)
        for s, e, old, new, _ in cites:
            if a.list:
                print(f"{path}:{line_of(s)}: {old!r} -> {new!r}")
            else:
                why = "no section of the project's documents known for it" if new is None else f"cite {new}"
                problems.append(f"{path}:{line_of(s)}: {old!r} cites the definition, which a clone lacks ({why})")
        for m in re.finditer(re.escape(SPEC), text):
            if not any(s <= m.start() < e for s, e, *_ in cites):
                problems.append(f"{path}:{line_of(m.start())}: names {SPEC}, which a clone lacks")
        for m in DOC_CITE.finditer(text):
            doc = m.group("doc")
            if doc == SPEC:
                continue
            rel = doc if doc.startswith("docs/") else None
            if rel is None:
                # `SCORE.md §5` from anywhere: the project's docs folder, else beside the file.
                for cand in ("docs/" + doc, os.path.join(os.path.dirname(path), doc), doc):
                    if os.path.isfile(os.path.join(ROOT, cand)):
                        rel = os.path.normpath(cand)
                        break
            if rel is None or not os.path.isfile(os.path.join(ROOT, rel)):
                problems.append(f"{path}:{line_of(m.start())}: {m.group(0)!r}: {doc} is not in the clone")
                continue
            if rel not in heads:
                heads[rel] = headings(rel)
            for n in (m.group("a"), m.group("b")):
                if n and n not in heads[rel]:
                    problems.append(f"{path}:{line_of(m.start())}: {m.group(0)!r}: {rel} has no section {n}")
        if path == "docs/SCORE.md":
            if path not in heads:
                heads[path] = headings(path)
            for m in BARE_CITE.finditer(text):
                for n in (m.group("a"), m.group("b")):
                    if n and n not in heads[path]:
                        problems.append(f"{path}:{line_of(m.start())}: {m.group(0)!r}: no section {n} in SCORE.md")
    if a.fix:
        print(f"cite-docs --fix: {changed} file(s) rewritten")
    if a.list:
        return
    for p in problems:
        print(p, file=sys.stderr)
    if a.check:
        if problems:
            print(f"cite-docs --check: FAILED: {len(problems)} citation(s) of a document or section "
                  "the clone lacks (scripts/cite-docs.py --fix rewrites the definition's)", file=sys.stderr)
            sys.exit(1)
        print("cite-docs --check: every citation names a document and section of the clone")


if __name__ == "__main__":
    main()
