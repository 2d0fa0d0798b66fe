"""MkDocs hook (mkdocs.yml `hooks:`): the package's docstrings cross-reference in Sphinx's roles
(:class:`Run`, :func:`load_run`); mkdocstrings renders the name as code and leaves the role's
prefix as text. This drops the prefix, so the API pages show `Run`, not :class:`Run`."""

from __future__ import annotations

import re

ROLE = re.compile(r":(?:class|func|meth|mod|data|attr|exc|obj|const|py:\w+):(?=<code>)")


def on_page_content(html: str, **kwargs) -> str:
    """The page's HTML without the role prefixes in front of code spans."""
    return ROLE.sub("", html)
