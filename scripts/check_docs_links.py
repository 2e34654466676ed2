#!/usr/bin/python3
"""Every relative link of the documentation resolves, and the file names the map pages give exist.

    /usr/bin/python3 scripts/check_docs_links.py [ROOT]

Reads README.md, CHANGELOG.md, docs/**/*.md, results/README.md and scenes/README.md under ROOT
(default: the repository this script is in). A link [text](target) or image ![alt](target) outside
code whose target is not a URL must name a file or folder that exists, relative to the page; a
"#anchor" must be a heading of the page it points to (GitHub's anchors: lower case, punctuation
dropped, spaces as hyphens, "-1", "-2" … for repeats). On the pages of PATH_PAGES every `code span`
that names a path under a top-level folder of the repository (`apps/scene.h`,
`apps/scene.{h,cpp}`, `tests/apps/`, `bench/*_bench.cpp`; a program by its source:
`bench/sweep_bench`) must exist too; spans with a placeholder
(<scene>, NAME) and build outputs (build/, results/default/) are not paths of the tree. A study
page's paths may name files under results/ (`thesis_A_a/sweep.h5`).
Exit code 0 when everything resolves, 1 otherwise (each problem named with page and line).
"""
import glob
import os
import re
import sys

PAGES = ["README.md", "CHANGELOG.md", "docs/**/*.md", "results/README.md", "scenes/README.md"]
PATH_PAGES = re.compile(r"^(README\.md|docs/[^/]+\.md|docs/levels/[^/]+\.md|docs/studies/[^/]+\.md)$")
RESULTS_PAGES = re.compile(r"^docs/studies/")  # their paths name files under results/ where one exists
NOT_IN_TREE = ("build/", "build-dev/", "results/default/", "/tmp/")

LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
HEADING = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")


def without_code(lines):
    """The lines with fenced blocks blanked and code spans removed (links there are not links)."""
    fenced, out = False, []
    for line in lines:
        if line.lstrip().startswith("```"):
            fenced = not fenced
            out.append("")
        else:
            out.append("" if fenced else CODE_SPAN.sub("", line))
    return out


def slug(heading):
    """GitHub's anchor of a heading: the rendered text (code spans verbatim, links by their text,
    emphasis markers dropped) in lower case, letters, digits, '-', '_' and spaces kept, spaces as
    hyphens."""
    text = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", heading)
    parts = re.split(r"(`[^`]*`)", text)
    text = "".join(p[1:-1] if p.startswith("`") else p.replace("*", "") for p in parts)
    kept = "".join(c for c in text.lower() if c.isalnum() or c in " -_")
    return kept.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen, found = {}, set()
        for line in without_code(open(path, encoding="utf-8").read().splitlines()):
            m = HEADING.match(line)
            if m:
                base = slug(m.group(2))
                n = seen.get(base, 0)
                seen[base] = n + 1
                found.add(base if n == 0 else f"{base}-{n}")
        # Headings inside code spans were blanked above; read them again with the spans kept.
        for line in open(path, encoding="utf-8").read().splitlines():
            m = HEADING.match(line)
            if m:
                found.add(slug(m.group(2)))
        cache[path] = found
    return cache[path]


def expand(path):
    """apps/scene.{h,cpp} → apps/scene.h, apps/scene.cpp."""
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    return [q for alt in m.group(1).split(",") for q in expand(path[:m.start()] + alt + path[m.end():])]


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    tops = {d + "/" for d in os.listdir(root) if os.path.isdir(os.path.join(root, d)) and not d.startswith(".")}
    tops -= {d for d in tops if d.startswith("build")}
    pages = sorted({p for pattern in PAGES for p in glob.glob(os.path.join(root, pattern), recursive=True)})
    problems, links, paths = [], 0, 0
    for page in pages:
        name = os.path.relpath(page, root)
        raw = open(page, encoding="utf-8").read().splitlines()
        for number, line in enumerate(without_code(raw), 1):
            for target in LINK.findall(line):
                if re.match(r"^[a-z]+:", target):
                    continue
                links += 1
                file, _, anchor = target.partition("#")
                resolved = os.path.normpath(os.path.join(os.path.dirname(page), file)) if file else page
                if not os.path.exists(resolved):
                    problems.append(f"{name}:{number}: link to {target}: no such file or folder")
                elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                    problems.append(f"{name}:{number}: link to {target}: no heading with that anchor in "
                                    f"{os.path.relpath(resolved, root)}")
        if not PATH_PAGES.match(name):
            continue
        fenced = False
        for number, line in enumerate(raw, 1):
            if line.lstrip().startswith("```"):
                fenced = not fenced
                continue
            if fenced:
                continue
            for _, span in CODE_SPAN.findall(line):
                span = span.strip()
                if (" " in span or not any(span.startswith(t) for t in tops) or "<" in span
                        or re.search(r"[A-Z]{2,}", span) or span.startswith(NOT_IN_TREE)):
                    continue
                for path in expand(span.rstrip(".,;:")):
                    paths += 1
                    # A program is named by its build output (bench/sweep_bench): its source counts.
                    bases = [root, os.path.join(root, "results")] if RESULTS_PAGES.match(name) else [root]
                    if not any(glob.glob(os.path.join(base, path + ext))
                               for base in bases for ext in ("", ".cpp", ".sh", ".py")):
                        problems.append(f"{name}:{number}: `{span}`: {path} is not in the tree")
    for p in problems:
        print(f"FAILS   {p}")
    print(f"{'holds' if not problems else 'FAILS'}   {links} relative links and {paths} file names on "
          f"{len(pages)} pages: {len(problems)} do not resolve")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
