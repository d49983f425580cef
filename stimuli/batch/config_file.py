"""The YAML file of a batch config: read it safely and bounded, find a key's line, write the resolved one.

A config file is refused before it is parsed when it is not a regular file
(a FIFO would block forever) or is larger than ``MAX_CONFIG_BYTES``; while
it is composed, nesting deeper than ``MAX_DEPTH`` and documents whose
aliases expand to more than ``MAX_NODES`` values are refused, each with
one line naming the file, and so is a mapping that gives a key twice (YAML
would silently keep the last value). Only the safe loader is used; it is
shared with every other YAML input of the project (the experiment's
settings).
"""

from __future__ import annotations

import os
import stat

from attneave.stimuli.errors import InputError
from attneave.stimuli.io import check_regular_file
from attneave.stimuli.stimulus_set import to_jsonable

__all__ = ["MAX_CONFIG_BYTES", "MAX_DEPTH", "MAX_NODES", "read_text", "parse_yaml", "yaml_line", "dumper", "resolved_text"]

MAX_CONFIG_BYTES = 1_000_000  # a config is typed by hand; anything larger is a mistake
MAX_DEPTH = 50  # YAML nesting; deeper would only exhaust the parser's recursion
MAX_NODES = 1_000_000  # YAML values counted with aliases expanded (a "billion laughs" file)


def read_text(path):
    """The config's text; a FIFO, a device or a file over MAX_CONFIG_BYTES is refused unread."""
    # checked before open(): opening a FIFO for reading blocks until someone writes to it
    check_regular_file(path, "a YAML config file")
    try:
        with open(path, "rb") as fh:
            info = os.fstat(fh.fileno())
            if not stat.S_ISREG(info.st_mode):
                raise InputError(f"{path}: not a regular file (a YAML config file was expected)")
            raw = fh.read(MAX_CONFIG_BYTES + 1)
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory (a YAML config file was expected)") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror or exc})") from None
    if len(raw) > MAX_CONFIG_BYTES:
        raise InputError(f"{path}: larger than {MAX_CONFIG_BYTES} bytes; a batch config is a short YAML file")
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not UTF-8 text (byte {exc.start})") from None


def parse_yaml(text, path):
    """(composed root node, data) of a YAML text, with its nesting and size bounded."""
    import yaml

    class Loader(yaml.SafeLoader):
        depth = 0

        def compose_node(self, parent, index):
            # bound the nesting while composing, before the recursion runs out
            self.depth += 1
            if self.depth > MAX_DEPTH:
                mark = self.peek_event().start_mark
                raise InputError(f"{path}:{mark.line + 1}: nested deeper than {MAX_DEPTH} levels")
            try:
                return super().compose_node(parent, index)
            finally:
                self.depth -= 1

        def compose_mapping_node(self, anchor):
            node = super().compose_mapping_node(anchor)
            _refuse_duplicate_keys(node, path)
            return node

    loader = Loader(text)
    try:
        root = loader.get_single_node()
        if root is None:
            return None, None
        n = _expanded_size(root)
        if n > MAX_NODES:
            raise InputError(f"{path}: {n} values once its aliases are expanded; the limit is {MAX_NODES}")
        return root, loader.construct_document(root)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark is not None else f"{path}"
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise InputError(f"{where}: invalid YAML: {problem}") from None
    finally:
        loader.dispose()


def _refuse_duplicate_keys(node, path):
    """InputError naming the file, the key and both its lines when a mapping gives a key twice."""
    import yaml

    seen = {}
    for key, _ in node.value:
        if not isinstance(key, yaml.ScalarNode) or key.tag == "tag:yaml.org,2002:merge":
            continue  # a complex key, or '<<' (a merge of an alias, whose keys the mapping's own override)
        ident = (key.tag, key.value)
        if ident in seen:
            raise InputError(f"{path}:{key.start_mark.line + 1}: duplicate key {key.value!r} (first given on "
                             f"line {seen[ident] + 1}); give each key once")
        seen[ident] = key.start_mark.line
    return node


def _expanded_size(root):
    """Number of values in the document with every alias expanded (shared nodes counted once each)."""
    import yaml

    sizes = {}

    def size(node):
        key = id(node)
        if key not in sizes:
            sizes[key] = 1  # a recursive alias counts once rather than forever
            if isinstance(node, yaml.MappingNode):
                sizes[key] += sum(size(k) + size(v) for k, v in node.value)
            elif isinstance(node, yaml.SequenceNode):
                sizes[key] += sum(size(v) for v in node.value)
        return sizes[key]

    return size(root)


def yaml_line(root, loc):
    """1-based line of the YAML node at `loc` (or of its deepest existing parent)."""
    if root is None:
        return None
    import yaml

    node = root
    line = node.start_mark.line + 1
    for p in loc:
        if isinstance(node, yaml.MappingNode) and isinstance(p, str):
            for k, v in node.value:
                if getattr(k, "value", None) == p:
                    line = k.start_mark.line + 1
                    node = v
                    break
            else:
                return line
        elif isinstance(node, yaml.SequenceNode) and isinstance(p, int) and 0 <= p < len(node.value):
            node = node.value[p]
            line = node.start_mark.line + 1
        else:
            return line
    if not isinstance(node, (yaml.MappingNode, yaml.SequenceNode)):
        line = node.start_mark.line + 1
    return line


def dumper():
    """A safe YAML dumper that writes lists of scalars on one line: ``[3, 5]``."""
    import yaml

    class Dumper(yaml.SafeDumper):
        """Safe dumper that writes lists of scalars on one line: ``[3, 5]``."""

    def represent_list(dumper, data):
        flow = all(not isinstance(v, (dict, list)) for v in data)
        return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=flow)

    Dumper.add_representer(list, represent_list)
    return Dumper


def resolved_text(seed, output, canvas, style, conditions):
    """The text of the resolved ``config.yaml``: defaults filled in, the package version."""
    import yaml

    from attneave.stimuli import __version__

    doc = {
        "attneave_version": __version__,
        "seed": seed,
        "canvas": canvas,
        "output": output,
        "style": style,
        "conditions": [
            {
                "name": c.name,
                "recipe": c.recipe,
                "params": c.params,
                "grid": c.axes,
                "repeats": c.repeats,
                "style": c.style,
                "canvas": c.canvas,
            }
            for c in conditions
        ],
    }
    header = (
        "# Resolved batch config written by `attneave generate` (defaults filled in).\n"
        "# Rerunning it gives the same files: attneave generate config.yaml -o DIR\n"
    )
    body = yaml.dump(to_jsonable(doc), Dumper=dumper(), sort_keys=False, default_flow_style=False,
                     allow_unicode=True, width=4096)
    return header + body
