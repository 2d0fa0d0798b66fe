"""The documentation site: `mkdocs build --strict` (warnings are errors: a broken link, a missing
anchor or a docstring mkdocstrings cannot read fails it), every internal link and anchor of the
built site resolves, and every code example of docs/ runs.

Code examples: ```python blocks are executed in order, one namespace per page; in ```sh blocks
every line that starts with `feeddrive` runs as that command (other lines — make, activate,
dask — are not run); ```json blocks must parse. A block directly after the comment
`<!-- docs-test: skip REASON -->` is not run (the reason names what covers it instead). The
examples run in a scratch folder holding a copy of examples/ and the built FMUs in build/, so
the commands write nothing into the repository. Skipped with the reason when mkdocs or
mkdocstrings is not installed (`make` installs them: python/pyproject.toml, extra `docs`).
"""

from __future__ import annotations

import json
import os
import re
import shlex
import shutil
import subprocess
import sys
from dataclasses import dataclass
from html.parser import HTMLParser
from importlib.util import find_spec
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SKIP = re.compile(r"^<!--\s*docs-test:\s*skip\s+(?P<why>.+?)\s*-->$")
FENCE = re.compile(r"^```(?P<lang>[\w-]*)\s*$")


def _env() -> dict[str, str]:
    env = dict(os.environ, NO_MKDOCS_2_WARNING="1", MPLBACKEND="Agg")
    env["PYTHONPATH"] = os.pathsep.join(
        p for p in (str(ROOT / "python"), env.get("PYTHONPATH")) if p
    )
    return env


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    missing = [m for m in ("mkdocs", "mkdocstrings", "material") if find_spec(m) is None]
    if missing:
        pytest.skip(
            f"{', '.join(missing)} not installed (pip install 'feeddrive[docs]'; make installs it)"
        )
    out = tmp_path_factory.mktemp("site")
    p = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(out)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=_env(),
        timeout=600,
    )
    assert p.returncode == 0, p.stderr[-4000:]
    assert "WARNING" not in p.stderr, p.stderr[-4000:]
    return out


def test_the_site_builds_strict_with_every_page(site):
    pages = sorted(f.relative_to(DOCS).with_suffix(".html") for f in DOCS.rglob("*.md"))
    assert pages and all((site / p).is_file() for p in pages), [
        p for p in pages if not (site / p).is_file()
    ]
    # the generated pages hold what they are generated from
    assert "friction.F_s" in (site / "parameters.html").read_text()
    assert "Plant" in (site / "api" / "fmu.html").read_text()
    assert "Keep a Changelog" in (site / "changelog.html").read_text()


class _Links(HTMLParser):
    """The ids and the link targets (href, src) of one HTML page."""

    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.targets: list[str] = []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name") if tag == "a" else ("id",):
            if a.get(key):
                self.ids.add(a[key])
        for key in ("href", "src"):
            if a.get(key) and not (
                tag == "link" and a.get("rel") in ("preconnect", "dns-prefetch")
            ):
                self.targets.append(a[key])


def _parse(path: Path) -> _Links:
    p = _Links()
    p.feed(path.read_text(encoding="utf-8"))
    return p


def broken_links(site: Path) -> list[str]:
    """Every internal href/src of the built site whose file or anchor does not exist."""
    site = site.resolve()
    pages = {f.resolve(): _parse(f) for f in site.rglob("*.html")}
    bad = []
    for page, links in pages.items():
        for target in links.targets:
            parts = urlsplit(target)
            if parts.scheme or parts.netloc or target.startswith("//"):
                continue  # external: not checked here
            if not parts.path:
                dest = page
            elif parts.path.startswith("/"):  # root-relative (the 404 page's)
                dest = (site / unquote(parts.path).lstrip("/")).resolve()
            else:
                dest = (page.parent / unquote(parts.path)).resolve()
            if parts.path.endswith("/") or dest.is_dir():
                dest = dest / "index.html"
            if not dest.exists():
                bad.append(f"{page.relative_to(site)}: {target} (no such file)")
                continue
            frag = unquote(parts.fragment)
            if frag and dest.suffix == ".html":
                ids = pages[dest].ids if dest in pages else _parse(dest).ids
                if frag not in ids:
                    bad.append(f"{page.relative_to(site)}: {target} (no anchor #{frag})")
    return bad


def test_every_internal_link_and_anchor_of_the_site_resolves(site):
    assert not broken_links(site), "\n".join(broken_links(site))


def test_the_link_check_finds_a_broken_link_and_anchor(site, tmp_path):
    copy = tmp_path / "site"
    shutil.copytree(site, copy)
    (copy / "extra.html").write_text(
        '<a href="index.html#no-such-anchor">x</a> <a href="gone.html">y</a>'
        '<img src="img/none.png"> <a href="quickstart.html#install">ok</a>'
    )
    found = broken_links(copy)
    assert len(found) == 3, found


# --- code examples ---------------------------------------------------------------------------


@dataclass
class Block:
    page: Path
    line: int
    lang: str
    code: str
    skip: str | None


def blocks(page: Path) -> list[Block]:
    """The fenced code blocks of a Markdown page, with the skip reason of each."""
    out: list[Block] = []
    lines = page.read_text(encoding="utf-8").splitlines()
    k = 0
    while k < len(lines):
        m = FENCE.match(lines[k])
        if not m:
            k += 1
            continue
        start = k
        k += 1
        body = []
        while k < len(lines) and lines[k].strip() != "```":
            body.append(lines[k])
            k += 1
        prev = next((lines[j].strip() for j in range(start - 1, -1, -1) if lines[j].strip()), "")
        skip = SKIP.match(prev)
        out.append(
            Block(page, start + 1, m["lang"], "\n".join(body), skip["why"] if skip else None)
        )
        k += 1
    return out


def _commands(code: str) -> list[list[str]]:
    """The `feeddrive ...` lines of a shell block (continuations joined, comments dropped)."""
    cmds = []
    for line in code.replace("\\\n", " ").splitlines():
        words = shlex.split(line, comments=True)
        if words and words[0] == "feeddrive":
            cmds.append(words[1:])
    return cmds


PAGES = sorted(DOCS.rglob("*.md"))
RUNNABLE = [
    p for p in PAGES if any(b.lang in ("python", "sh", "json") and not b.skip for b in blocks(p))
]


def test_every_skipped_example_says_why():
    for page in PAGES:
        for b in blocks(page):
            if b.skip is not None:
                assert len(b.skip.split()) >= 3, (
                    f"{page}:{b.line}: give the reason and what covers it"
                )


def test_the_block_reader_sees_skips_and_commands(tmp_path):
    page = tmp_path / "p.md"
    page.write_text(
        "text\n\n<!-- docs-test: skip takes an hour; test_x covers it -->\n```sh\nfeeddrive a \\\n  --b c"
        "   # note\nmake x\n```\n\n```python\nx = 1\n```\n"
    )
    (b1, b2) = blocks(page)
    assert (b1.lang, b1.skip, b2.lang, b2.skip) == (
        "sh",
        "takes an hour; test_x covers it",
        "python",
        None,
    )
    assert _commands(b1.code) == [["a", "--b", "c"]]


@pytest.fixture()
def scratch(tmp_path, monkeypatch) -> Path:
    """A folder with a copy of examples/ and the built FMUs in build/ (skip when not built)."""
    fmus = sorted((ROOT / "build").glob("*.fmu"))
    if not (ROOT / "build" / "LinearMotorFeedDrive.fmu").exists():
        pytest.skip("the FMUs are not built (make fmu)")
    shutil.copytree(ROOT / "examples", tmp_path / "examples")
    (tmp_path / "build").mkdir()
    for f in fmus:
        (tmp_path / "build" / f.name).symlink_to(f)
    monkeypatch.chdir(tmp_path)
    return tmp_path


@pytest.mark.slow
@pytest.mark.parametrize("page", RUNNABLE, ids=lambda p: str(p.relative_to(DOCS)))
def test_code_examples_run(page, scratch):
    namespace: dict = {"__name__": "__docs__"}
    for b in blocks(page):
        if b.skip:
            continue
        where = f"{page.relative_to(ROOT)}:{b.line}"
        if b.lang == "python":
            exec(compile(b.code, where, "exec"), namespace)
        elif b.lang == "json":
            json.loads(b.code)
        elif b.lang == "sh":
            for args in _commands(b.code):
                p = subprocess.run(
                    [sys.executable, "-m", "feeddrive.cli", *args],
                    cwd=scratch,
                    capture_output=True,
                    text=True,
                    env=_env(),
                    timeout=600,
                )
                assert p.returncode == 0, (
                    f"{where}: feeddrive {shlex.join(args)}\n{p.stdout[-2000:]}{p.stderr[-2000:]}"
                )
