#!/usr/bin/python3
"""Checks that a fresh Debian 12 machine that installs only scripts/debian-packages.txt has
everything the project uses: every system header it includes, every tool its scripts, Makefile,
launch files and tests run, and every Python module its tests and scripts import must come from a
package that the list brings in (the list itself or what its packages depend on).

A package installed by hand on a development machine hides a missing install step (it happened
with libcli11-dev: the build passed there and stopped on a fresh machine). Everything is read from
dpkg's database, so the check needs no network and no apt lists.

    test/check_install_list.py [--root DIR] [--list FILE]

Exit 0 when everything is covered; 1 naming each header (or tool, or module), the package that
owns it and the files that use it; 2 for bad usage."""
import argparse
import importlib.util
import os
import re
import shutil
import subprocess
import sys
from collections import defaultdict

# Tools run by name from scripts and the Makefile, with the files that run them. Each entry is
# checked against its files (a tool no longer mentioned there is reported, so the table stays
# true); launch-file nodes and Python imports are found by reading the files themselves.
TOOLS = {
    "Xvfb": ["scripts/demo.sh"],
    "import": ["scripts/demo.sh"],  # imagemagick's screenshot tool
    "roslaunch": ["scripts/demo.sh", "scripts/soak.py"],
    "python3": ["scripts/demo.sh"],
    "gnuplot": ["src/core/io/gnuplot.cpp", "scripts/soak.py"],
    "cmake": ["Makefile"],
    "ctest": ["Makefile"],
    "ccache": ["Makefile"],
    "clang-format": ["Makefile"],
}

INCLUDE = re.compile(r'^\s*#\s*include\s*<([^>]+)>')
PY_IMPORT = re.compile(r'^\s*(?:import|from)\s+([A-Za-z_][A-Za-z0-9_]*)')
LAUNCH_TAG = re.compile(r'<(?:node|test)((?:\s+[\w:-]+\s*=\s*"[^"]*")*)')  # values may hold '>'
ATTRIBUTE = re.compile(r'([\w:-]+)\s*=\s*"([^"]*)"')
SOURCE_DIRS = ("include", "src", "test", "bench", "tools")


def read_dpkg_status(path="/var/lib/dpkg/status"):
    """Installed packages: name -> (depends, pre-depends) strings; and virtual name -> providers."""
    installed, provides = {}, defaultdict(list)
    with open(path, encoding="utf-8", errors="replace") as f:
        for block in f.read().split("\n\n"):
            fields, key = {}, None
            for line in block.splitlines():
                if line.startswith((" ", "\t")) and key:
                    fields[key] += " " + line.strip()
                elif ":" in line:
                    key, _, value = line.partition(":")
                    fields[key] = value.strip()
            if "install ok installed" not in fields.get("Status", ""):
                continue
            name = fields["Package"]
            installed[name] = fields.get("Depends", "") + "," + fields.get("Pre-Depends", "")
            for p in fields.get("Provides", "").split(","):
                p = p.split("(")[0].strip()
                if p:
                    provides[p].append(name)
    return installed, provides


def closure_of(wanted, installed, provides):
    """Packages that installing `wanted` brings in: Depends and Pre-Depends, recursively (the
    install script passes --no-install-recommends). Of alternatives, the first one that is
    installed here (or provided by an installed package) is what apt would have chosen."""
    def resolve(name):
        name = name.split(":")[0]
        if name in installed:
            return [name]
        return [p for p in provides.get(name, []) if p in installed]

    seen, stack = set(), list(wanted)
    while stack:
        pkg = stack.pop()
        if pkg in seen:
            continue
        seen.add(pkg)
        for group in installed.get(pkg, "").split(","):
            for alternative in group.split("|"):
                name = re.sub(r"\(.*?\)|\[.*?\]|<.*?>", "", alternative).strip()
                found = resolve(name) if name else []
                if found:
                    stack.extend(found)
                    break
    return seen


def owners(paths):
    """dpkg -S for many paths at once: path -> owning packages (diversions ignored)."""
    result = {}
    paths = sorted(set(paths))
    for i in range(0, len(paths), 200):
        out = subprocess.run(["dpkg", "-S"] + paths[i:i + 200], capture_output=True,
                             text=True).stdout
        for line in out.splitlines():
            if line.startswith("diversion by"):
                continue
            pkgs, _, path = line.partition(": ")
            result[path.strip()] = [p.split(":")[0].strip() for p in pkgs.split(",")]
    return result


def owned_path(path):
    """dpkg knows a file by the path it unpacked it to; /bin is a symlink to /usr/bin on a
    merged-/usr Debian 12, so try both spellings and the resolved path."""
    candidates = [path, os.path.realpath(path)]
    for p in list(candidates):
        if p.startswith("/usr/"):
            candidates.append(p[len("/usr"):])
        else:
            candidates.append("/usr" + p)
    return candidates


def project_files(root, dirs, suffixes):
    for top in dirs:
        for base, subdirs, files in os.walk(os.path.join(root, top)):
            subdirs[:] = [d for d in subdirs if d not in ("__pycache__", "build")]
            for f in files:
                if f.endswith(suffixes):
                    yield os.path.join(base, f)


def system_headers(root):
    """<...> includes of the project that are not its own: header -> including files."""
    own = {os.path.relpath(p, os.path.join(root, "include"))
           for p in project_files(root, ("include",), ("",))}
    users = defaultdict(set)
    for p in project_files(root, SOURCE_DIRS, (".h", ".hpp", ".cpp", ".cc")):
        for line in open(p, errors="replace"):
            m = INCLUDE.match(line)
            if m:
                users[m.group(1)].add(os.path.relpath(p, root))
    # <vector> and friends have neither a directory nor a dot: the compiler's own.
    return {h: u for h, u in users.items() if ("/" in h or "." in h) and h not in own}


def locate_headers(headers):
    """Header -> file under /usr/include (the shortest path that ends in the include's name)."""
    index = defaultdict(list)
    for base, _, files in os.walk("/usr/include"):
        for f in files:
            index[f].append(os.path.join(base, f))
    found = {}
    for h in headers:
        cands = [p for p in index.get(os.path.basename(h), []) if p.endswith("/" + h)]
        if cands:
            found[h] = min(cands, key=len)
    return found


def launch_executables(root):
    """Executables that the launch and rostest files start: (pkg/type) -> using files."""
    uses = defaultdict(set)
    for p in project_files(root, ("launch", "test"), (".launch", ".test")):
        for attributes in LAUNCH_TAG.findall(open(p, errors="replace").read()):
            a = dict(ATTRIBUTE.findall(attributes))
            if "pkg" in a and "type" in a and a["pkg"] != "cloth_hair_sim":
                uses[(a["pkg"], a["type"])].add(os.path.relpath(p, root))
    return uses


def find_ros_executable(pkg, typ):
    for d in ("/usr/lib/%s" % pkg, "/usr/share/%s" % pkg, "/usr/lib/%s/scripts" % pkg):
        p = os.path.join(d, typ)
        if os.path.isfile(p):
            return p
    return shutil.which(typ, path="/usr/bin:/bin")


def python_imports(root):
    """Top-level modules the project's Python imports: module -> using files."""
    uses = defaultdict(set)
    files = list(project_files(root, ("test", "scripts"), (".py",)))
    for p in files:
        for line in open(p, errors="replace"):
            m = PY_IMPORT.match(line)
            if m:
                uses[m.group(1)].add(os.path.relpath(p, root))
    # Python run inline from shell scripts (python3 - <<'PY' ... PY).
    for p in project_files(root, ("scripts",), (".sh",)):
        text = open(p, errors="replace").read()
        for body in re.findall(r"<<'PY'\n(.*?)\nPY", text, re.S):
            for line in body.splitlines():
                m = PY_IMPORT.match(line)
                if m:
                    uses[m.group(1)].add(os.path.relpath(p, root))
    local = {os.path.splitext(os.path.basename(p))[0] for p in files}
    return {m: u for m, u in uses.items() if m not in local and m != "cloth_hair_sim"}


def module_file(module):
    # The system python is the one the tests run with (a pyenv python lacks the ROS modules).
    spec = importlib.util.find_spec(module)
    if spec is None:
        return None
    if spec.origin in (None, "built-in", "frozen"):
        return "built-in"
    return spec.origin


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(__file__), ".."))
    ap.add_argument("--list", help="install list (default: ROOT/scripts/debian-packages.txt)")
    args = ap.parse_args()
    root = os.path.realpath(args.root)
    list_file = args.list or os.path.join(root, "scripts/debian-packages.txt")
    if not os.path.isfile(list_file):
        print("check_install_list: no install list %s" % list_file)
        return 2
    wanted = [l.split("#")[0].strip() for l in open(list_file)]
    wanted = [w for w in wanted if w]
    installed, provides = read_dpkg_status()
    not_installed = [w for w in wanted if w not in installed]
    closure = closure_of(wanted, installed, provides)

    problems = []  # (what, name, owner or None, users)
    headers = system_headers(root)
    located = locate_headers(headers)
    for h in sorted(set(headers) - set(located)):
        problems.append(("header", h, None, headers[h]))

    tools = {}
    for tool, files in TOOLS.items():
        stale = [f for f in files
                 if not re.search(r"(^|[^\w-])%s([^\w-]|$)" % re.escape(tool),
                                  open(os.path.join(root, f), errors="replace").read())]
        if stale:
            problems.append(("tool", tool, "listed in check_install_list.py but not used by",
                             stale))
        path = shutil.which(tool, path="/usr/bin:/bin")
        if path:
            tools[("tool", tool)] = (path, files)
        else:
            problems.append(("tool", tool, None, files))
    for (pkg, typ), files in launch_executables(root).items():
        path = find_ros_executable(pkg, typ)
        name = "%s/%s" % (pkg, typ)
        if path:
            tools[("launch node", name)] = (path, sorted(files))
        else:
            problems.append(("launch node", name, None, files))
    modules = {}
    for module, files in python_imports(root).items():
        path = module_file(module)
        if path is None:
            problems.append(("python module", module, None, files))
        elif path != "built-in":
            modules[module] = (path, sorted(files))

    files = list(located.values()) + [p for p, _ in tools.values()] + \
        [p for p, _ in modules.values()]
    owner = owners([c for f in files for c in owned_path(f)])

    def owner_of(path):
        for c in owned_path(path):
            if c in owner:
                return owner[c]
        return None

    def check(kind, name, path, users):
        pk = owner_of(path)
        if pk is None:
            problems.append((kind, name, "%s belongs to no Debian package" % path, users))
        elif not any(p in closure for p in pk):
            problems.append((kind, name, pk[0], users))

    for h, path in sorted(located.items()):
        check("header", h, path, headers[h])
    for (kind, name), (path, users) in sorted(tools.items()):
        check(kind, name, path, users)
    for module, (path, users) in sorted(modules.items()):
        if path.startswith(root):  # generated into the build tree
            continue
        check("python module", module, path, users)

    print("check_install_list: %d packages listed (%d with what they depend on), %d system "
          "headers, %d tools and launch nodes, %d python modules" %
          (len(wanted), len(closure), len(headers), len(tools), len(modules)))
    if not_installed:
        print("check_install_list: listed but not installed here (run scripts/install-deps.sh): "
              + ", ".join(not_installed))
    for kind, name, pk, users in problems:
        used = ", ".join(sorted(users))
        if pk is None:
            print("MISSING %s %s: not installed here by any package (used by %s)" %
                  (kind, name, used))
        elif " " in pk:
            print("MISSING %s %s: %s %s" % (kind, name, pk, used))
        else:
            print("MISSING %s %s: from package %s, which %s does not bring in (used by %s)" %
                  (kind, name, pk, os.path.relpath(list_file, root), used))
    if problems or not_installed:
        return 1
    print("check_install_list: every header, tool and module comes from the install list")
    return 0


if __name__ == "__main__":
    sys.exit(main())
