#!/usr/bin/env python3
"""Checks, without Docker, that deploy/docker/Dockerfile can build its image:

1. the build stage COPYs every folder the top-level CMakeLists.txt adds outside its test
   and benchmark blocks (a new folder such as robots/ must reach the image's build);
2. both stages install every shared library the binaries link: for each binary the Dockerfile builds, the libraries it names
(objdump's NEEDED) are mapped to their Debian packages (dpkg -S), and each package must be
in the dependency closure (apt-cache depends --recurse) of both the build stage's and the
runtime stage's apt-get install lists. A library the code starts to use (prometheus-cpp,
jemalloc) but the Dockerfile forgets fails here, not at the first image build.

    image_check.py DOCKERFILE BIN_DIR
Prints one line per problem and exits 1 if there is any; exits 0 with a summary if not.
"""
import os
import re
import subprocess
import sys

# A package name on an apt-get install line (not a flag, a variable, a shell word).
WORD = re.compile(r"^[a-z0-9][a-z0-9+.-]+$")
NOT_PACKAGES = {"apt-get", "install", "update", "rm", "run"}


def stage_packages(dockerfile):
    """{stage name: set of packages its apt-get install lines name}."""
    text = re.sub(r"\\\n", " ", open(dockerfile).read())
    stages, name = {}, None
    for line in text.splitlines():
        words = line.split()
        if words and words[0] == "FROM":
            name = words[-1] if "AS" in words else str(len(stages))
            stages[name] = set()
        elif name and "apt-get install" in line:
            install = line[line.index("apt-get install"):].split("&&")[0].split()
            stages[name] |= {w for w in install if WORD.match(w) and w not in NOT_PACKAGES}
    return stages


def built_binaries(dockerfile):
    text = re.sub(r"\\\n", " ", open(dockerfile).read())
    m = re.search(r"ninja -C \S+ -j \S+ ([^&]+)&&", text)
    if not m:
        sys.exit(f"{dockerfile}: no 'ninja -C DIR -j N TARGETS' line to read the binaries from")
    return m.group(1).split()


def missing_sources(dockerfile):
    """Folders the top-level CMakeLists.txt adds (tests and bench aside) that no COPY brings."""
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(dockerfile))))
    cmake, depth, needed = open(os.path.join(repo, "CMakeLists.txt")).read(), 0, []
    for line in cmake.splitlines():
        line = line.split("#")[0].strip()
        if re.match(r"if\s*\(GAITFORGE_BUILD_(TESTS|BENCH)\)", line):
            depth += 1
        elif depth and re.match(r"endif\s*\(", line):
            depth -= 1
        elif not depth:
            needed += re.findall(r"add_subdirectory\(\s*([\w/.-]+)", line)
            needed += [os.path.dirname(f) for f in re.findall(r"include\(\s*([\w/.-]+\.cmake)", line)]
    text = re.sub(r"\\\n", " ", open(dockerfile).read())
    copied = {w.rstrip("/") for line in text.splitlines() if line.startswith("COPY ")
              for w in line.split()[1:-1] if not w.startswith("--")}
    return [d for d in needed if d and d.rstrip("/") not in copied]


def needed_packages(binary):
    """{package: [sonames]} of the libraries the binary names directly."""
    dump = subprocess.run(["objdump", "-p", binary], capture_output=True, text=True, check=True)
    sonames = re.findall(r"NEEDED\s+(\S+)", dump.stdout)
    ldd = subprocess.run(["ldd", binary], capture_output=True, text=True, check=True).stdout
    paths = dict(re.findall(r"^\s*(\S+) => (\S+)", ldd, re.M))
    owners = {}
    for so in sonames:
        path = os.path.realpath(paths.get(so, so))
        found = subprocess.run(["dpkg", "-S", path], capture_output=True, text=True)
        if found.returncode != 0:  # merged /usr: dpkg knows /lib/..., ldd says /usr/lib/...
            found = subprocess.run(["dpkg", "-S", path.removeprefix("/usr")],
                                   capture_output=True, text=True)
        pkg = found.stdout.split(":")[0] if found.returncode == 0 else f"<no package owns {path}>"
        owners.setdefault(pkg, []).append(so)
    return owners


def closure(packages):
    out = subprocess.run(
        ["apt-cache", "depends", "--recurse", "--no-recommends", "--no-suggests",
         "--no-conflicts", "--no-breaks", "--no-replaces", "--no-enhances", *sorted(packages)],
        capture_output=True, text=True).stdout
    return {line.split(":")[0] for line in out.splitlines() if line and not line[0].isspace()}


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    dockerfile, bin_dir = sys.argv[1], sys.argv[2]
    stages = stage_packages(dockerfile)
    problems, checked = [f"{dockerfile}: the build stage does not COPY {d}/, which "
                         f"CMakeLists.txt adds" for d in missing_sources(dockerfile)], set()
    closures = {s: closure(p) for s, p in stages.items() if s in ("build", "runtime")}
    if set(closures) != {"build", "runtime"}:
        sys.exit(f"{dockerfile}: expected stages 'build' and 'runtime', found {sorted(stages)}")
    for binary in built_binaries(dockerfile):
        for pkg, sonames in needed_packages(os.path.join(bin_dir, binary)).items():
            checked.add(pkg)
            for stage, have in closures.items():
                if pkg not in have:
                    problems.append(f"{dockerfile}: the {stage} stage lacks {pkg} "
                                    f"({', '.join(sonames)}, linked by {binary})")
    print("\n".join(problems) if problems else
          f"sources copied; {len(checked)} library packages of the image's binaries are in both stages")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
