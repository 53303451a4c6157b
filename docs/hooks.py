"""mkdocs hook: the Sphinx roles of our docstrings (``:func:`name```) as links to the API
reference where it documents the name, as code otherwise (mkdocstrings reads the docstrings
as Markdown, which has no roles)."""

import re

_ROLE = re.compile(r":(?:mod|func|class|meth|attr|data|exc|obj):<code>~?([\w.]+)</code>")


def on_page_content(html, **kwargs):
    return _ROLE.sub(lambda m: f'<autoref identifier="{m.group(1)}" optional><code>{m.group(1)}</code></autoref>',
                     html)
