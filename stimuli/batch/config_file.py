"""The YAML file of a batch config: read it with the safe loader, find a key's line."""

from __future__ import annotations

from stimuli.errors import InputError

__all__ = ["read_text", "parse_yaml", "yaml_line", "dumper"]



def read_text(path):
    """The config's text."""
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise InputError(f"{path}: no such file") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read ({exc})") from None


def parse_yaml(text, path):
    """(composed root node, data) of a YAML text, parsed once with the safe loader."""
    import yaml

    loader = yaml.SafeLoader(text)
    try:
        root = loader.get_single_node()
        if root is None:
            return None, None
        return root, loader.construct_document(root)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        where = f"{path}:{mark.line + 1}:{mark.column + 1}" if mark is not None else f"{path}"
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise InputError(f"{where}: invalid YAML: {problem}") from None
    finally:
        loader.dispose()


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
    import yaml

    class Dumper(yaml.SafeDumper):
        """Safe dumper that writes lists of scalars on one line: ``[3, 5]``."""

    def represent_list(dumper, data):
        flow = all(not isinstance(v, (dict, list)) for v in data)
        return dumper.represent_sequence("tag:yaml.org,2002:seq", data, flow_style=flow)

    Dumper.add_representer(list, represent_list)
    return Dumper
