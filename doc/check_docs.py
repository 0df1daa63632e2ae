#!/usr/bin/python3
"""Checks impm's documentation, and regenerates its deck reference.

  python3 doc/check_docs.py --impm build/apps/impm            check (exit 1 on a problem)
  python3 doc/check_docs.py --impm build/apps/impm --write    regenerate the reference, then check
  python3 doc/check_docs.py --links-only                       check the links only (no impm needed)

The deck reference is the block of doc/user-guide.md between the lines
<!-- BEGIN GENERATED DECK REFERENCE --> and <!-- END GENERATED DECK REFERENCE -->. It is made from
the schema that impm validates every deck against: `impm --help` (each key's type, default,
choices and documentation) and `impm --print-defaults` (each default as YAML). The check fails
when the block differs from what the binary prints (the schema changed and the reference was
not regenerated), and when a relative link in README.md or doc/*.md names a file that does not
exist or a heading anchor (GitHub's rule: lower case, punctuation dropped, spaces to hyphens,
-1, -2, ... for repeats) that the target file does not have. Links to web addresses are not
followed. Only the Python standard library is used; the output is deterministic.
"""
import argparse
import difflib
import os
import re
import subprocess
import sys
import urllib.parse

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
GUIDE = os.path.join("doc", "user-guide.md")
BEGIN = "<!-- BEGIN GENERATED DECK REFERENCE -->"
END = "<!-- END GENERATED DECK REFERENCE -->"


# ---------------------------------------------------------------------------------------------
# The schema, from the binary


class Node:
    """A sublist of the deck schema: its documentation, parameters and sublists, in order."""

    def __init__(self, name, doc=""):
        self.name = name
        self.doc = doc
        self.params = []  # dicts: name, type, default, doc, choices, range
        self.subs = []  # Nodes


def run_impm(impm, flag):
    try:
        out = subprocess.run([impm, flag], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             universal_newlines=True, timeout=120, check=False)
    except OSError as e:
        sys.exit("check_docs: cannot run %s %s: %s" % (impm, flag, e))
    except subprocess.TimeoutExpired:
        sys.exit("check_docs: %s %s did not finish within 120 s" % (impm, flag))
    if out.returncode != 0:
        sys.exit("check_docs: %s %s exited with %d:\n%s" % (impm, flag, out.returncode, out.stderr))
    return out.stdout


PARAM_RE = re.compile(r"^( *)(\S.*?) : (string|int|double|bool) =(?: (.*))?$")
SUB_RE = re.compile(r"^( *)(\S.*?) -> ?$")
COMMENT_RE = re.compile(r"^( *)#(.*)$")
INT_EXTREMES = {"-2147483648", "2147483647"}


def parse_help(text):
    """Parses the 'Valid parameters' part of `impm --help` (Teuchos' printDoc) into a Node tree."""
    lines = text.splitlines()
    start = next((i for i, l in enumerate(lines) if l.startswith("Valid parameters")), None)
    if start is None:
        sys.exit("check_docs: `impm --help` printed no 'Valid parameters' list")
    root = Node("")
    stack = [(-1, root)]  # (indent, node)
    item = None  # the parameter dict or Node that comment lines belong to
    quoted = None  # collecting a Teuchos 'Valid std::string values' list
    for line in lines[start + 1:]:
        if not line.strip() or line.strip() == "[empty list]":
            continue
        m = COMMENT_RE.match(line)
        if m:
            body = m.group(2)
            if item is None:
                continue
            info = body.strip()
            if quoted is not None:
                if info == "}":
                    item["choices"] = quoted
                    quoted = None
                elif info.startswith('"') and info.endswith('"'):
                    quoted.append(info[1:-1])
                continue
            if body.startswith(" ") and not body.startswith("  ") and not body.startswith(" \t"):
                # documentation (Teuchos writes '# text'; validator lines are indented further)
                if isinstance(item, Node):
                    item.doc = (item.doc + " " + info).strip()
                else:
                    item["doc"] = (item["doc"] + " " + info).strip()
                continue
            if info.startswith("Acceptable Values:"):
                values = info[len("Acceptable Values:"):].strip()
                if values.startswith("{") and values.endswith("}"):
                    item["choices"] = [v.strip() for v in values[1:-1].split(",") if v.strip()]
            elif info.startswith("Valid std::string values:"):
                quoted = []
            elif info.startswith("Min (inclusive):") and not isinstance(item, Node):
                v = info.split(":", 1)[1].strip()
                if v not in INT_EXTREMES:
                    item["range"][0] = v
            elif info.startswith("Max (inclusive):") and not isinstance(item, Node):
                v = info.split(":", 1)[1].strip()
                if v not in INT_EXTREMES:
                    item["range"][1] = v
            continue
        m = PARAM_RE.match(line) or SUB_RE.match(line)
        if not m:
            sys.exit("check_docs: cannot read this line of `impm --help`: %r" % line)
        indent = len(m.group(1))
        while stack[-1][0] >= indent:
            stack.pop()
        parent = stack[-1][1]
        if m.re is PARAM_RE:
            item = {"name": m.group(2), "type": m.group(3), "default": m.group(4) or "", "doc": "",
                    "choices": [], "range": [None, None]}
            parent.params.append(item)
        else:
            item = Node(m.group(2))
            parent.subs.append(item)
            stack.append((indent, item))
    return root


def parse_defaults(text):
    """Parses `impm --print-defaults` (Teuchos' YAML writer: two spaces per level) into dicts."""
    root = {}
    stack = [(-1, root)]
    for line in text.splitlines():
        if not line.strip() or line.startswith("%") or line.strip() in ("---", "..."):
            continue
        indent = len(line) - len(line.lstrip(" "))
        key, sep, value = line.strip().partition(":")
        if not sep:
            sys.exit("check_docs: cannot read this line of `impm --print-defaults`: %r" % line)
        value = value.strip()
        while stack[-1][0] >= indent:
            stack.pop()
        parent = stack[-1][1]
        if value == "":
            parent[key] = {}
            stack.append((indent, parent[key]))
        elif value == "{ }":
            parent[key] = {}
        else:
            parent[key] = value
    return root.get("impm", root)


def attach_defaults(node, defaults, path, problems):
    """Takes each parameter's default from --print-defaults (as a deck writes it)."""
    for p in node.params:
        if p["name"] not in defaults or isinstance(defaults[p["name"]], dict):
            problems.append("%s: in `impm --help` but not a parameter of `impm --print-defaults`"
                            % "/".join(path + [p["name"]]))
            p["yaml"] = None
        else:
            p["yaml"] = defaults[p["name"]]
    for s in node.subs:
        key = s.name
        if key == "<name>":  # a collection: --print-defaults shows one entry, 'example'
            key = next((k for k, v in defaults.items() if isinstance(v, dict)), None)
        if key not in defaults or not isinstance(defaults[key], dict):
            problems.append("%s: in `impm --help` but not a sublist of `impm --print-defaults`"
                            % "/".join(path + [s.name]))
            continue
        attach_defaults(s, defaults[key], path + [s.name], problems)
    known = {p["name"] for p in node.params} | {s.name for s in node.subs}
    for k in defaults:
        if k not in known and not any(s.name == "<name>" for s in node.subs):
            problems.append("%s: in `impm --print-defaults` but not in `impm --help`"
                            % "/".join(path + [k]))


# ---------------------------------------------------------------------------------------------
# The reference, as markdown


def md_text(text):
    """Escapes text for a markdown table cell; code spans (`...`) are kept as they are."""
    parts = text.split("`")
    if len(parts) % 2 == 0:  # an unpaired backtick: escape it too
        parts = [text.replace("`", "\\`")]
    out = []
    for i, part in enumerate(parts):
        if i % 2 == 1:
            out.append("`" + part.replace("|", "\\|") + "`")
            continue
        s = []
        for j, c in enumerate(part):
            if c == "|":
                s.append("\\|")
            elif c == "<":
                s.append("&lt;")
            elif c == ">":
                s.append("&gt;")
            elif c == "*":
                s.append("\\*")
            elif c == "_":
                before = part[j - 1] if j > 0 else " "
                after = part[j + 1] if j + 1 < len(part) else " "
                s.append("_" if before.isalnum() and after.isalnum() else "\\_")
            else:
                s.append(c)
        out.append("".join(s))
    return "".join(out)


def sentence(text):
    text = text.strip()
    if text and text[0].isalpha():
        text = text[0].upper() + text[1:]
    if text and not text.endswith("."):
        text += "."
    return text


def code(value):
    return "`" + value.replace("|", "\\|") + "`"


def default_cell(p):
    # Numbers as --help prints them (shortest form), booleans as a deck writes them (true, false).
    v = p["default"]
    if p["type"] == "bool" and p["yaml"] is not None:
        v = p["yaml"]
    if v in ("", "''"):
        return "(empty)"
    return code(v)


def meaning_cell(p):
    text = md_text(p["doc"]) if p["doc"] else ""
    extra = []
    if p["choices"]:
        extra.append("One of " + ", ".join(code(c) for c in p["choices"]) + ".")
    lo, hi = p["range"]
    if lo is not None or hi is not None:
        extra.append("Range %s to %s." % (lo if lo is not None else "-inf", hi if hi is not None else "inf"))
    if text and not text.endswith("."):
        text += "."
    return " ".join([text] + extra).strip()


def render_node(node, path, depth, out):
    title = "/".join(path)
    out.append("#" * min(depth, 6) + " " + code(title))
    out.append("")
    if node.doc:
        out.append(md_text(sentence(node.doc)))
        out.append("")
    rows = list(node.params)
    # Sublists without parameters of their own (passed to a Trilinos package) are table rows.
    leaf_subs = [s for s in node.subs if not s.params and not s.subs]
    if rows or leaf_subs:
        out.append("| key | type | default | meaning |")
        out.append("|---|---|---|---|")
        for p in rows:
            out.append("| %s | %s | %s | %s |" % (code(p["name"]), p["type"], default_cell(p), meaning_cell(p)))
        for s in leaf_subs:
            doc = s.doc.strip()
            if doc and not doc.endswith("."):
                doc += "."
            out.append("| %s | sublist | (empty) | %s |" % (code(s.name), md_text(doc)))
        out.append("")
    for s in node.subs:
        if s in leaf_subs:
            continue
        render_node(s, path + [s.name], depth + 1, out)


def reference(impm):
    tree = parse_help(run_impm(impm, "--help"))
    defaults = parse_defaults(run_impm(impm, "--print-defaults"))
    problems = []
    attach_defaults(tree, defaults, [], problems)
    if problems:
        sys.exit("check_docs: `impm --help` and `impm --print-defaults` disagree:\n  " + "\n  ".join(problems))
    out = [BEGIN,
           "<!-- Generated by `python3 doc/check_docs.py --impm build/apps/impm --write` from `impm --help`",
           "     and `impm --print-defaults`; edit the schema's documentation in the C++ code, not this block. -->",
           ""]
    for s in tree.subs:
        render_node(s, [s.name], 3, out)
    out.append(END)
    return "\n".join(out) + "\n"


def split_guide(text):
    b = text.find(BEGIN)
    e = text.find(END)
    if b < 0 or e < 0 or e < b:
        sys.exit("check_docs: %s lacks the lines %s and %s" % (GUIDE, BEGIN, END))
    e += len(END)
    if text[e:e + 1] == "\n":
        e += 1
    return text[:b], text[b:e], text[e:]


# ---------------------------------------------------------------------------------------------
# Links

FENCE_RE = re.compile(r"^\s*(```|~~~)")
HEADING_RE = re.compile(r"^(#{1,6})\s+(.*?)\s*#*\s*$")
LINK_RE = re.compile(r"!?\[(?:[^\[\]]|\[[^\]]*\])*\]\(\s*<?([^)\s>]*)>?(?:\s+(?:\"[^\"]*\"|'[^']*'))?\s*\)")
REFDEF_RE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s.*)?$")
HTML_ANCHOR_RE = re.compile(r"<a\s+(?:[^>]*\s)?(?:id|name)\s*=\s*\"([^\"]+)\"", re.I)
HTML_HREF_RE = re.compile(r"<(?:a|img)\s+[^>]*(?:href|src)\s*=\s*\"([^\"]+)\"", re.I)


def prose_lines(text):
    """(line number, line) outside fenced code blocks, with inline code spans blanked."""
    fence = None
    for n, line in enumerate(text.splitlines(), 1):
        m = FENCE_RE.match(line)
        if m:
            if fence is None:
                fence = m.group(1)
            elif m.group(1) == fence:
                fence = None
            continue
        if fence is None:
            yield n, line


def strip_code_spans(line):
    return re.sub(r"(`+)(.+?)\1", lambda m: " " * len(m.group(0)), line)


def slug(heading):
    """GitHub's anchor of a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links: their text
    text = re.sub(r"<[^>]+>", "", text)  # HTML tags
    text = text.replace("`", "").replace("*", "")
    text = text.strip().lower()
    text = "".join(c for c in text if c.isalnum() or c in "-_ ")
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        with open(path, encoding="utf-8") as f:
            text = f.read()
        seen = {}
        result = set()
        for _, line in prose_lines(text):
            m = HEADING_RE.match(line)
            if m:
                s = slug(m.group(2))
                k = seen.get(s, 0)
                seen[s] = k + 1
                result.add(s if k == 0 else "%s-%d" % (s, k))
            for a in HTML_ANCHOR_RE.findall(line):
                result.add(a)
        cache[path] = result
    return cache[path]


def link_targets(text):
    for n, line in prose_lines(text):
        bare = strip_code_spans(line)
        for m in LINK_RE.finditer(bare):
            yield n, m.group(1)
        m = REFDEF_RE.match(bare)
        if m:
            yield n, m.group(1)
        for t in HTML_HREF_RE.findall(bare):
            yield n, t


def check_links():
    files = ["README.md"] + sorted(os.path.join("doc", f) for f in os.listdir(os.path.join(REPO, "doc"))
                                   if f.endswith(".md"))
    problems = []
    count = 0
    for rel in files:
        with open(os.path.join(REPO, rel), encoding="utf-8") as f:
            text = f.read()
        for n, target in link_targets(text):
            if not target or re.match(r"^[A-Za-z][A-Za-z0-9+.-]*:", target) or target.startswith("//"):
                continue  # web addresses, mailto: and the like are not followed
            count += 1
            path, _, anchor = target.partition("#")
            path = urllib.parse.unquote(path)
            if path:
                dest = os.path.normpath(os.path.join(os.path.dirname(rel), path))
            else:
                dest = rel
            full = os.path.join(REPO, dest)
            where = "%s:%d: link '%s'" % (rel, n, target)
            if dest.startswith(".."):
                problems.append("%s: points outside the repository" % where)
                continue
            if not os.path.exists(full):
                problems.append("%s: no file %s" % (where, dest))
                continue
            if anchor:
                if not dest.endswith(".md") or os.path.isdir(full):
                    problems.append("%s: an anchor on %s, which is not a markdown file" % (where, dest))
                elif urllib.parse.unquote(anchor) not in anchors(full):
                    problems.append("%s: no heading with the anchor '#%s' in %s" % (where, anchor, dest))
    return files, count, problems


# ---------------------------------------------------------------------------------------------


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--impm", default=os.path.join(REPO, "build", "apps", "impm"),
                    help="the impm binary whose schema the reference documents (default: build/apps/impm)")
    ap.add_argument("--write", action="store_true",
                    help="regenerate the deck reference in doc/user-guide.md instead of comparing it")
    ap.add_argument("--links-only", action="store_true", help="check the links only (impm is not run)")
    args = ap.parse_args()

    failed = False
    guide = os.path.join(REPO, GUIDE)
    if not args.links_only:
        if not os.path.isfile(args.impm):
            sys.exit("check_docs: no impm binary at %s (give --impm PATH, or --links-only)" % args.impm)
        with open(guide, encoding="utf-8") as f:
            text = f.read()
        head, block, tail = split_guide(text)
        fresh = reference(args.impm)
        if args.write:
            if block != fresh:
                with open(guide, "w", encoding="utf-8") as f:
                    f.write(head + fresh + tail)
                print("check_docs: %s: deck reference regenerated from %s" % (GUIDE, args.impm))
            else:
                print("check_docs: %s: deck reference already up to date" % GUIDE)
        elif block != fresh:
            failed = True
            diff = list(difflib.unified_diff(block.splitlines(), fresh.splitlines(),
                                             "%s (deck reference)" % GUIDE, "%s --help/--print-defaults" % args.impm,
                                             lineterm="", n=1))
            print("check_docs: FAIL: the deck reference in %s differs from the schema of %s;" % (GUIDE, args.impm))
            print("  regenerate it: python3 doc/check_docs.py --impm %s --write" % args.impm)
            for line in diff[:60]:
                print("  " + line)
            if len(diff) > 60:
                print("  ... (%d more diff lines)" % (len(diff) - 60))
        else:
            print("check_docs: %s: deck reference matches %s" % (GUIDE, args.impm))

    files, count, problems = check_links()
    if problems:
        failed = True
        print("check_docs: FAIL: %d broken relative link(s):" % len(problems))
        for p in problems:
            print("  " + p)
    else:
        print("check_docs: %d relative links in %d files resolve (%s)" % (count, len(files), ", ".join(files)))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
