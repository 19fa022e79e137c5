"""Every relative link of README.md and docs/*.md resolves: the file exists and, for
`path#anchor`, the target Markdown file has a heading with that slug (GitHub's rule)."""

import glob
import os
import re

import pytest

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
PAGES = [os.path.join(REPO, "README.md")] + sorted(glob.glob(os.path.join(REPO, "docs", "*.md")))

# [text](target) and ![alt](target); the target up to whitespace or ')'
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
FENCE = re.compile(r"^\s*(```|~~~)")
INLINE_CODE = re.compile(r"`[^`]*`")


def prose_lines(text):
    """(line number, line) outside fenced code blocks, inline code removed."""
    fenced = False
    for i, line in enumerate(text.splitlines(), 1):
        if FENCE.match(line):
            fenced = not fenced
            continue
        if not fenced:
            yield i, INLINE_CODE.sub("", line)


def slug(heading):
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    s = re.sub(r"<[^>]+>", "", heading).strip().lower()
    s = s.replace("`", "")
    s = re.sub(r"[^\w\- ]", "", s)
    return s.replace(" ", "-")


def anchors(path):
    """Every heading slug of a Markdown file (repeats numbered as GitHub does)."""
    seen = {}
    out = set()
    fenced = False
    for line in open(path, encoding="utf-8").read().splitlines():
        if FENCE.match(line):
            fenced = not fenced
            continue
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if fenced or not m:
            continue
        s = slug(m.group(1))
        n = seen.get(s, 0)
        seen[s] = n + 1
        out.add(s if n == 0 else f"{s}-{n}")
    return out


def links(page):
    """(line, target) of every relative link (a link's text may span lines)."""
    text = open(page, encoding="utf-8").read()
    numbered = list(prose_lines(text))
    prose = "\n".join(p for _, p in numbered)
    for m in LINK.finditer(prose):
        target = m.group(1)
        if re.match(r"^[a-z][a-z0-9+.-]*:", target):  # http:, https:, mailto:
            continue
        yield numbered[prose.count("\n", 0, m.start(1))][0], target


def test_slug_follows_githubs_rule():
    assert slug("`greybox identify` — recordings from any rig → friction dataset") == "greybox-identify--recordings-from-any-rig--friction-dataset"
    assert slug("Reciprocating tests (ASTM G133)") == "reciprocating-tests-astm-g133"


def broken_links(page):
    """Each link of `page` whose file or heading is missing, as 'line: target (why)'."""
    broken = []
    for line, target in links(page):
        path, _, anchor = target.partition("#")
        dest = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        if not os.path.exists(dest):
            broken.append(f"{line}: {target} (no such file)")
        elif anchor and dest.endswith(".md") and anchor not in anchors(dest):
            broken.append(f"{line}: {target} (no heading '{anchor}')")
    return broken


def test_the_check_finds_broken_links(tmp_path):
    (tmp_path / "other.md").write_text("# Other page\n\n## A `code` heading (yes)\n")
    page = tmp_path / "page.md"
    page.write_text(
        "# Page\n[ok](other.md#a-code-heading-yes) [self](#page) [web](https://example.org/x)\n"
        "[gone](missing.md) and [a\nwrapped one](other.md#nope)\n"
        "```\n[in code](nothing.md)\n```\n`[inline](nothing.md)`\n"
    )
    assert broken_links(str(page)) == [
        "3: missing.md (no such file)",
        "4: other.md#nope (no heading 'nope')",
    ]


@pytest.mark.parametrize("page", PAGES, ids=[os.path.relpath(p, REPO) for p in PAGES])
def test_every_relative_link_resolves(page):
    broken = broken_links(page)
    assert broken == [], os.path.relpath(page, REPO) + "\n" + "\n".join(broken)
