#!/usr/bin/env python3
"""Check docs/scene-reference.md against the scene parser (issue 36).

The keys the parser accepts are read from the sources, so that the reference cannot drift:
  - src/io/scene.c: the section types (BUILDERS) and, per section, every literal key its builder
    reads (scene_get_*(t, s, "key"), the option and number tables), following the calls between
    the file's static functions and those of src/io/scene_walls.c;
  - [material]: the parameter table of src/particles/material.c (the keys of
    sinter_material_param_info; with the library at hand, sinter.Material.keys() too) and the
    keys build_material reads itself (the property tables);
  - [force NAME] / [heat NAME]: the built-in models' key tables (src/force, src/heat);
  - [electric NAME]: src/electric/electric.c;
  - [stepper]: also the quasi-static options (src/stepper/quasistatic.c, "qs_*");
  - [pair] of pair files (`sinter pair`): the keys read_plan of src/io/pair.c reads.
The reference documents a key as a table row "| `key` | ..." under a heading naming the section,
"## `[stepper]`" or "### `[heat laser]`". The check fails when a key is accepted but not
documented, or documented but not accepted. Run: python3 tests/docs/check_scene_reference.py
"""
import os
import re
import sys

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))


def read(rel):
    with open(os.path.join(ROOT, rel), encoding="utf-8") as f:
        return f.read()


def strip_comments(src):
    src = re.sub(r"/\*.*?\*/", " ", src, flags=re.S)
    return re.sub(r"//[^\n]*", " ", src)


def functions(src):
    """{name: body} of the top-level functions of a C file."""
    out = {}
    for m in re.finditer(r"^(?:static\s+)?[\w\s\*]+?\b(\w+)\s*\([^;{]*?\)\s*\{", src, re.M | re.S):
        depth, i = 0, m.end() - 1
        while i < len(src):
            if src[i] == "{":
                depth += 1
            elif src[i] == "}":
                depth -= 1
                if depth == 0:
                    break
            i += 1
        out[m.group(1)] = src[m.end():i]
    return out


KEY_CALL = re.compile(r'(?:scene_(?:get_\w+|find)|read_schedule)\s*\(\s*\w+\s*,\s*\w+\s*,\s*"(\w+)"',
                      re.S)
FIND_CALL = re.compile(r'scene_find\s*\(\s*\w+\s*,\s*"(\w+)"', re.S)


def direct_keys(body):
    keys = set(KEY_CALL.findall(body)) | set(FIND_CALL.findall(body))
    # tables of keys inside a builder: options[] = {"a", "b"} and {"key", &o->field}
    for table in re.findall(r"options\[\]\s*=\s*\{(.*?)\};", body, re.S):
        keys |= set(re.findall(r'"(\w+)"', table))
    keys |= set(re.findall(r'\{\s*"(\w+)"\s*,\s*&', body))
    return keys


def parser_keys():
    src = strip_comments(read("src/io/scene.c"))
    # the [wall] section's kinds, spin and servo, and the [insert] section, in their own files
    funcs = functions(src + "\n" + strip_comments(read("src/io/scene_walls.c")) + "\n" +
                      strip_comments(read("src/io/scene_insert.c")))
    builders = re.search(r"BUILDERS\[\]\s*=\s*\{(.*?)\};", src, re.S)
    if not builders:
        sys.exit("check_scene_reference: no BUILDERS table in src/io/scene.c")
    sections = dict(re.findall(r'\{\s*"(\w+)"\s*,\s*(\w+)\s*,', builders.group(1)))

    def closure(name, seen):
        if name in seen or name not in funcs:
            return set()
        seen.add(name)
        keys = direct_keys(funcs[name])
        for callee in re.findall(r"\b(\w+)\s*\(", funcs[name]):
            if callee in funcs and callee != name:
                keys |= closure(callee, seen)
        return keys

    accepted = {}
    for section, builder in sections.items():
        if builder not in funcs:
            sys.exit("check_scene_reference: builder %s not found in src/io/scene.c" % builder)
        accepted[section] = closure(builder, set())
    return accepted


def material_keys():
    src = read("src/particles/material.c")
    table = re.search(r"PARAMS\[[^\]]*\]\s*=\s*\{(.*?)\n\};", src, re.S)
    keys = set(re.findall(r'\{\s*"(\w+)"\s*,\s*"', table.group(1))) if table else set()
    if os.environ.get("SINTER_LIBRARY"):  # the library's own describe function, when built
        sys.path.insert(0, os.path.join(ROOT, "bindings", "python"))
        import sinter  # noqa: E402
        lib_keys = set(sinter.Material.keys())
        if lib_keys != keys:
            sys.exit("check_scene_reference: material.c's table and sinter_material_param_info "
                     "disagree: %s" % sorted(lib_keys ^ keys))
    return keys


def model_keys(folder, ops_type):
    """{model name: keys} of the built-in models whose ops are defined in folder/*.c."""
    models = {}
    for name in sorted(os.listdir(os.path.join(ROOT, folder))):
        if not name.endswith(".c"):
            continue
        src = strip_comments(read(os.path.join(folder, name)))
        for m in re.finditer(r"const\s+%s\s+\w+\s*=\s*\{(.*?)\};" % ops_type, src, re.S):
            body = m.group(1)
            model = re.search(r'"(\w+)"', body).group(1)
            keys_group = re.search(r"\{([^{}]*?)\bNULL\s*\}", body)
            models[model] = set(re.findall(r'"(\w+)"', keys_group.group(1))) if keys_group else set()
    return models


def electric_keys():
    src = strip_comments(read("src/electric/electric.c"))
    names = re.findall(r'\{\s*"(\w+)"\s*,\s*SINTER_ELECTRIC_\w+', src)
    keys = re.search(r"KEYS\[\w*\]\s*=\s*\{(.*?)\};", src, re.S)
    keys = set(re.findall(r'"(\w+)"', keys.group(1))) if keys else set()
    # the conductivity law's keys are the network model's only (electric.c refuses them on
    # the averaged model)
    network_only = {"sigmoid", "theta_ref", "k1", "gamma1"}
    return {n: keys if n == "network" else keys - network_only for n in names}


def scan_keys():
    """The scan path keys of beam models (src/io/scene_scan.c): those it reads, checked against
    the list with which build_heat sets them aside (scene_heat_scan_key)."""
    src = strip_comments(read("src/io/scene_scan.c"))
    funcs = functions(src)
    read_keys = set()
    for body in funcs.values():
        read_keys |= direct_keys(body)
    listed = re.search(r"keys\[\]\s*=\s*\{(.*?)\};", funcs.get("scene_heat_scan_key", ""), re.S)
    listed = set(re.findall(r'"(\w+)"', listed.group(1))) if listed else set()
    if not read_keys or read_keys != listed:
        sys.exit("check_scene_reference: scene_scan.c reads %s but sets aside %s"
                 % (sorted(read_keys), sorted(listed)))
    return read_keys


def quasistatic_keys():
    src = strip_comments(read("src/stepper/quasistatic.c"))
    return set(re.findall(r'"(qs_\w+)"', src))


def pair_keys():
    funcs = functions(strip_comments(read("src/io/pair.c")))
    if "read_plan" not in funcs:
        sys.exit("check_scene_reference: no read_plan in src/io/pair.c")
    return direct_keys(funcs["read_plan"])


def documented():
    """{(section, model or ''): keys} from the reference's headings and table rows."""
    doc = {}
    current = None
    for line in read("docs/scene-reference.md").splitlines():
        h = re.match(r"#+\s+`\[(\w+)(?:\s+(\w+))?\]`", line)
        if h:
            section, name = h.group(1), h.group(2) or ""
            if name.isupper():  # [material NAME], [wall NAME]: a placeholder
                name = ""
            current = (section, name)
            doc.setdefault(current, set())
            continue
        if line.startswith("#"):
            current = None
            continue
        row = re.match(r"\|\s*`(\w+)`\s*\|", line)
        if row and current:
            doc[current].add(row.group(1))
    return doc


def main():
    accepted = {(s, ""): k for s, k in parser_keys().items()}
    # the parameters, and the keys the material's builder reads itself (property tables)
    accepted[("material", "")] = material_keys() | accepted.get(("material", ""), set())
    accepted[("stepper", "")] |= quasistatic_keys()
    accepted[("pair", "")] = pair_keys()
    for section, models in (("force", model_keys("src/force", "sinter_force_ops")),
                            ("heat", model_keys("src/heat", "sinter_heat_ops")),
                            ("electric", electric_keys())):
        if accepted.get((section, "")):
            sys.exit("check_scene_reference: [%s] reads literal keys %s; teach this check"
                     % (section, sorted(accepted[(section, "")])))
        accepted.pop((section, ""), None)
        if not models:
            sys.exit("check_scene_reference: found no %s models in the sources" % section)
        for model, keys in models.items():
            accepted[(section, model)] = keys
            if section == "heat" and {"x", "y"} <= keys and keys & {"power", "intensity"}:
                accepted[(section, model)] = keys | scan_keys()  # a beam: it can follow a path
    # guard against a silently broken extraction
    for must in [("scene", ""), ("particles", ""), ("wall", ""), ("stepper", ""),
                 ("material", ""), ("output", ""), ("compact", ""), ("pour", ""), ("pair", "")]:
        if not accepted.get(must):
            sys.exit("check_scene_reference: extracted no keys for [%s]" % must[0])
    doc = documented()
    for section in ("force", "heat", "electric"):  # "## `[heat MODEL]`": an umbrella heading
        if not doc.get((section, ""), {"x"}):
            del doc[(section, "")]
    errors = []
    for where in sorted(set(accepted) | set(doc)):
        label = "[%s%s]" % (where[0], " " + where[1] if where[1] else "")
        if where not in doc:
            errors.append("%s: the parser accepts this section but the reference has no "
                          "heading for it" % label)
            continue
        if where not in accepted:
            errors.append("%s: documented, but the parser knows no such section or model" % label)
            continue
        for key in sorted(accepted[where] - doc[where]):
            errors.append("%s: key '%s' is accepted but not documented" % (label, key))
        for key in sorted(doc[where] - accepted[where]):
            errors.append("%s: key '%s' is documented but not accepted" % (label, key))
    if errors:
        print("docs/scene-reference.md and the scene parser disagree:")
        for e in errors:
            print("  " + e)
        return 1
    n = sum(len(k) for k in accepted.values())
    print("docs/scene-reference.md documents the %d keys of %d sections and models the parser "
          "accepts" % (n, len(accepted)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
