"""Edits of a cutting set-up's TOML text that keep its comments and layout: a key replaced or
added in a table, a key read, a table removed (the validation scripts' variants of a template).
Keys are addressed as `table.key` or, at the top level, `key`."""
import re


def sections(text):
    """The TOML text as [(header, lines)], the top level first with header ''."""
    out = [('', [])]
    for line in text.splitlines():
        m = re.match(r'^\[([^\[\]]+)\]\s*$', line)
        if m:
            out.append((m.group(1).strip(), []))
        else:
            out[-1][1].append(line)
    return out


def join(parts):
    text = []
    for header, lines in parts:
        if header:
            text.append(f'[{header}]')
        text.extend(lines)
    return '\n'.join(text) + '\n'


def set_key(parts, section, key, value):
    """`key = value` in `section` (replaced, else added at the section's top)."""
    for header, lines in parts:
        if header == section:
            pattern = re.compile(rf'^{re.escape(key)}\s*=')
            for i, line in enumerate(lines):
                if pattern.match(line):
                    lines[i] = f'{key} = {value}'
                    return
            lines.insert(0, f'{key} = {value}')
            return
    raise SystemExit(f'the template has no [{section}] table')


def get_key(parts, section, key):
    for header, lines in parts:
        if header == section:
            for line in lines:
                m = re.match(rf'^{re.escape(key)}\s*=\s*(.+?)\s*(#.*)?$', line)
                if m:
                    return m.group(1)
    raise SystemExit(f'the template has no {key} in [{section}]')


def remove_section(parts, section):
    return [(h, l) for h, l in parts if h != section]


def set_path(text, path, value):
    """The text with `path` (`key` or `table.key`, the table the longest dotted prefix that is
    one of the text's tables) set to `value`, a TOML value as written."""
    parts = sections(text)
    headers = {h for h, _ in parts}
    table, _, key = path.rpartition('.')
    while table and table not in headers:
        # a dotted key inside a table, e.g. material.thermal.conductivity
        head, _, last = table.rpartition('.')
        table, key = head, f'{last}.{key}'
    set_key(parts, table, key, value)
    return join(parts)
