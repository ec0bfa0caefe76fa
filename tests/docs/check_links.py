#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks that every internal link and image of a built HTML site resolves.

Usage: check_links.py HTML_DIR. For every .html file: each href and src that is not external
(http:, https:, mailto:, data:, javascript:) must name an existing file under HTML_DIR, and a
#fragment must be an id (or a name) in the target page.
"""
import html.parser
import pathlib
import sys
import urllib.parse

EXTERNAL = ("http:", "https:", "mailto:", "data:", "javascript:", "ftp:")


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids, self.refs = set(), []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name"):
            if a.get(key) and (key == "id" or tag == "a"):
                self.ids.add(a[key])
        for key in ("href", "src"):
            if a.get(key) is not None and not (tag == "link" and a.get("rel") in ("preconnect",)):
                self.refs.append((tag, key, a[key], self.getpos()[0]))


def parse(path, cache):
    if path not in cache:
        p = Page()
        p.feed(path.read_text(encoding="utf-8", errors="replace"))
        cache[path] = p
    return cache[path]


def main():
    root = pathlib.Path(sys.argv[1]).resolve()
    pages = sorted(root.rglob("*.html"))
    if not pages:
        sys.exit(f"check_links: no HTML under {root}")
    cache, errors, checked = {}, [], 0
    for page in pages:
        for tag, key, ref, line in parse(page, cache).refs:
            if not ref or ref.startswith(EXTERNAL):
                continue
            checked += 1
            url = urllib.parse.urlsplit(ref)
            if url.scheme and url.scheme != "file":
                errors.append(f"{page.relative_to(root)}:{line}: {tag} {key}={ref!r}: unexpected scheme")
                continue
            target = page if not url.path else (page.parent / urllib.parse.unquote(url.path)).resolve()
            if target.is_dir():
                target = target / "index.html"
            if root not in target.parents and target != root:
                errors.append(f"{page.relative_to(root)}:{line}: {key}={ref!r} leaves the site")
                continue
            if not target.exists():
                errors.append(f"{page.relative_to(root)}:{line}: {tag} {key}={ref!r}: no such file")
                continue
            if url.fragment and target.suffix == ".html":
                if urllib.parse.unquote(url.fragment) not in parse(target, cache).ids:
                    errors.append(f"{page.relative_to(root)}:{line}: {key}={ref!r}: no id "
                                  f"'{url.fragment}' in {target.relative_to(root)}")
    for e in errors:
        print("check_links:", e)
    print(f"check_links: {len(pages)} pages, {checked} internal links and images, "
          f"{len(errors)} broken")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
