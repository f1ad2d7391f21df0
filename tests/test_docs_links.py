"""Every relative link in the README and the docs resolves to a file inside the repository.

A clone has nothing beside it (no ``../shared``), so a link that leaves the checkout, or names a file
that is not there, is a dead link for every reader of the repository."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent

#: the pages a reader of the repository opens: the README, every page under docs/, and the folders' READMEs
PAGES = sorted(
    [ROOT / "README.md", *(ROOT / "docs").rglob("*.md"), *ROOT.glob("*/README.md")],
    key=lambda p: p.relative_to(ROOT).as_posix(),
)

#: [text](target) and ![alt](target), the target up to whitespace or ")"; an optional "title" after it
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
#: fenced code blocks and inline code spans hold no links
CODE = re.compile(r"^(```|~~~).*?^\1", flags=re.MULTILINE | re.DOTALL)
SPAN = re.compile(r"`[^`\n]*`")


def links(page: Path) -> list[str]:
    text = SPAN.sub("", CODE.sub("", page.read_text(encoding="utf-8")))
    return LINK.findall(text)


def relative(target: str) -> bool:
    """A link to a file of the repository, not a web address, mail address or anchor of the same page."""
    return not re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target) and not target.startswith("#")


def test_the_pages_are_found():
    names = {p.relative_to(ROOT).as_posix() for p in PAGES}
    assert {"README.md", "docs/method.md", "docs/library.md"} <= names


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_relative_link_resolves_inside_the_repository(page: Path):
    bad = []
    for target in filter(relative, links(page)):
        path = target.split("#", 1)[0].split("?", 1)[0]
        resolved = (page.parent / path).resolve()
        if not resolved.is_relative_to(ROOT):
            bad.append(f"{target} (outside the repository)")
        elif not resolved.exists():
            bad.append(f"{target} (no such file)")
    assert not bad, f"{page.relative_to(ROOT)}: " + ", ".join(bad)


def test_the_readme_names_nothing_beside_the_checkout():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert "../shared" not in text and "/work/" not in text


def test_links_are_parsed():
    page = 'see [a](docs/a.md), ![fig](b.png "t"), [c](https://x.org), `[d](no.md)`\n```\n[e](no.md)\n```\n'
    assert LINK.findall(SPAN.sub("", CODE.sub("", page))) == ["docs/a.md", "b.png", "https://x.org"]
    assert [t for t in LINK.findall(page) if relative(t)][:2] == ["docs/a.md", "b.png"]
