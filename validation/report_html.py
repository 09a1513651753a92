"""The report's HTML page: its Markdown rendered by markdown-it-py, in one self-contained file.

CommonMark plus GitHub-style tables (markdown-it-py's ``commonmark`` preset with ``table``
enabled); raw HTML in the Markdown is escaped. Images stay relative links to
``figures/*.png`` beside ``index.html``, so the page and its folder are the report (embedding
~50 PNGs as data URIs would triple the page's size for no gain when the folder travels
whole); the style sheet is inline, nothing is fetched. Each figure takes the page's column
width (about 1100 px, the PNGs' own size: their axis labels stay readable) and links to its
PNG, for the full size.
"""

from __future__ import annotations

import html
import re

_STYLE = """body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;}
table{border-collapse:collapse;margin:1em 0;font-size:0.9em}
td,th{border:1px solid #bbb;padding:3px 6px;text-align:left}
th{background:#eee}
img{display:block;max-width:100%;height:auto;margin:0.8em auto;border:1px solid #ddd}
code{background:#f4f4f4;padding:0 3px}"""


def to_html(markdown: str, title: str) -> str:
    """A complete HTML document for ``markdown`` with ``title``."""
    from markdown_it import MarkdownIt

    md = MarkdownIt("commonmark", {"html": False}).enable("table")
    body = _linked_images(md.render(markdown))
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title><style>{_STYLE}</style></head>\n"
            f"<body>\n{body}</body></html>\n")


_IMG = re.compile(r'<img src="([^"]*)"[^>]*>')


def _linked_images(body: str) -> str:
    """Every ``<img>`` of the rendered ``body`` wrapped in a link to its own file (the
    markdown's image paths, already escaped by the renderer)."""
    return _IMG.sub(lambda m: f'<a href="{m.group(1)}">{m.group(0)}</a>', body)
