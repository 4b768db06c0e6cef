# SPDX-License-Identifier: LGPL-2.1-or-later
"""The documentation holds together: every relative link in README.md and docs/ points at
a file of the repository (and, with a #fragment into a Markdown file, at one of its
headings), every docs page is reachable from docs/README.md, and every "design N.M"
section the medial code cites is a heading of docs/design/medial.md."""

import os
import re

import pytest

_HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(_HERE))
DOCS = os.path.join(REPO, "docs")

# [text](target) and [text](target "title"); images too.  Code spans are removed first.
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^(```|~~~)")


def markdown_files():
    files = [os.path.join(REPO, "README.md")]
    for root, _dirs, names in os.walk(DOCS):
        files += [os.path.join(root, n) for n in sorted(names) if n.endswith(".md")]
    return sorted(files)


def prose(path):
    """The file's lines outside fenced code blocks, with inline code spans blanked."""
    out, fenced = [], False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line.lstrip()):
                fenced = not fenced
                continue
            if not fenced:
                out.append(re.sub(r"`[^`]*`", "``", line))
    return out


def slug(heading):
    """GitHub's anchor of a heading: lower case, markup and punctuation dropped (hyphens
    and underscores kept), spaces to hyphens."""
    h = heading.strip().lower()
    h = re.sub(r"[`*]", "", h)
    h = re.sub(r"\[([^\]]*)\]\([^)]*\)", r"\1", h)
    h = re.sub(r"[^\w\- ]", "", h)
    return h.replace(" ", "-")


def anchors(path):
    seen, out = {}, set()
    fenced = False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if FENCE.match(line.lstrip()):
                fenced = not fenced
                continue
            m = None if fenced else re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
            if m:
                s = slug(m.group(1))
                n = seen.get(s, 0)
                seen[s] = n + 1
                out.add(s if n == 0 else "%s-%d" % (s, n))
    return out


def links(path):
    for lineno, line in enumerate(prose(path), 1):
        for m in LINK.finditer(line):
            yield lineno, m.group(1)


def test_there_is_documentation():
    files = markdown_files()
    assert os.path.join(DOCS, "README.md") in files
    assert len(files) > 10


@pytest.mark.parametrize("path", markdown_files(), ids=lambda p: os.path.relpath(p, REPO))
def test_relative_links_resolve(path):
    bad = []
    for lineno, target in links(path):
        if re.match(r"^[a-z][a-z0-9+.-]*:", target, re.I):   # http:, https:, mailto:
            continue
        file_part, _, frag = target.partition("#")
        dest = path if not file_part else os.path.normpath(
            os.path.join(os.path.dirname(path), file_part))
        if not os.path.exists(dest):
            bad.append("line %d: %s (no such file)" % (lineno, target))
        elif not dest.startswith(REPO + os.sep):
            bad.append("line %d: %s (outside the repository)" % (lineno, target))
        elif frag and dest.endswith(".md") and frag not in anchors(dest):
            bad.append("line %d: %s (no heading #%s in %s)"
                       % (lineno, target, frag, os.path.relpath(dest, REPO)))
    assert not bad, "%s:\n  %s" % (os.path.relpath(path, REPO), "\n  ".join(bad))


def test_every_docs_page_is_reachable_from_the_index():
    """Every page under docs/ can be reached from docs/README.md by following links."""
    start = os.path.join(DOCS, "README.md")
    seen, todo = {start}, [start]
    while todo:
        page = todo.pop()
        for _lineno, target in links(page):
            file_part = target.partition("#")[0]
            if not file_part or re.match(r"^[a-z][a-z0-9+.-]*:", file_part, re.I):
                continue
            dest = os.path.normpath(os.path.join(os.path.dirname(page), file_part))
            if dest.endswith(".md") and dest.startswith(DOCS + os.sep) \
                    and os.path.exists(dest) and dest not in seen:
                seen.add(dest)
                todo.append(dest)
    pages = {p for p in markdown_files() if p.startswith(DOCS + os.sep)}
    assert not sorted(pages - seen), "not reachable from docs/README.md: %s" % [
        os.path.relpath(p, REPO) for p in sorted(pages - seen)]


# "design 4.1", "design section 4.1", "(design 1.3 [choice])", "docs/design/medial.md
# section 4.1", "design 3's step 4": the section number after it.
CITE = re.compile(r"(?:\bdesign|docs/design/medial\.md)[,:]?\s+(?:sections?\s+)?(\d+(?:\.\d+)?)\b")
MEDIAL_SOURCES = [os.path.join(REPO, "libcore", "src", "medial"),
                  os.path.join(REPO, "libcore", "tests", "medial")]


def medial_citations():
    found = {}
    for folder in MEDIAL_SOURCES:
        for root, _dirs, names in os.walk(folder):
            for n in sorted(names):
                if n.endswith((".c", ".h")):
                    p = os.path.join(root, n)
                    with open(p, encoding="utf-8") as f:
                        text = f.read()
                    for m in CITE.finditer(text):
                        found.setdefault(m.group(1), os.path.relpath(p, REPO))
    for n in sorted(os.listdir(os.path.join(REPO, "tests", "python"))):
        if n.startswith("medial") and n.endswith(".py"):
            p = os.path.join(REPO, "tests", "python", n)
            with open(p, encoding="utf-8") as f:
                for m in CITE.finditer(f.read()):
                    found.setdefault(m.group(1), os.path.relpath(p, REPO))
    return found


def test_medial_design_sections_the_code_cites_exist():
    with open(os.path.join(DOCS, "design", "medial.md"), encoding="utf-8") as f:
        heads = set(re.findall(r"^#{2,4}\s+(\d+(?:\.\d+)?)\.?\s", f.read(), re.M))
    cited = medial_citations()
    assert cited, "no design citation found in the medial code"
    missing = {s: where for s, where in cited.items() if s not in heads}
    assert not missing, "sections cited but not in docs/design/medial.md: %s" % missing


# "docs/design/axis2d.md section 2", "docs/design/medial.md, sections 3 and 5" anywhere in
# the sources and tests: the file exists and has a numbered heading of that section.
PATH_CITE = re.compile(r"docs/(design/[\w-]+\.md)[,:]?\s+(?:sections?\s+)?(\d+(?:\.\d+)?)\b")


def test_cited_docs_sections_exist():
    bad = []
    heads_of = {}
    for top in ("libcore", "tests", "workbench", "bench"):
        for root, _dirs, names in os.walk(os.path.join(REPO, top)):
            for n in sorted(names):
                if not n.endswith((".c", ".h", ".py", ".sh", ".txt", ".cpp")):
                    continue
                p = os.path.join(root, n)
                try:
                    with open(p, encoding="utf-8") as f:
                        text = f.read()
                except UnicodeDecodeError:
                    continue
                for m in PATH_CITE.finditer(text):
                    doc = os.path.join(DOCS, m.group(1))
                    if doc not in heads_of:
                        heads_of[doc] = None
                        if os.path.exists(doc):
                            with open(doc, encoding="utf-8") as f:
                                heads_of[doc] = set(re.findall(
                                    r"^#{2,4}\s+(\d+(?:\.\d+)?)\.?\s", f.read(), re.M))
                    if heads_of[doc] is None or m.group(2) not in heads_of[doc]:
                        bad.append("%s: docs/%s section %s"
                                   % (os.path.relpath(p, REPO), m.group(1), m.group(2)))
    assert not bad, "cited sections that do not exist:\n  " + "\n  ".join(bad)
