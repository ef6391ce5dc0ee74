#!/usr/bin/env python3
"""The contents of a platform's extension zip (scripts/build-addon PLATFORM; docs/packaging.md):
its name and manifest carry CMake's version and the one platform, the executable is there and
executable, the presets and OpenColorIO config are there, and (Linux) every shared library the
executable needs is either bundled in bin/lib, found there through RUNPATH, or one of the base
system's (scripts/linux-base-libs), no file needs a glibc or libstdc++ newer than Ubuntu 22.04's, and
the relinked libexpat parses XML.
Usage: check_zip.py ZIP PLATFORM SOURCE_DIR"""
import os
import re
import subprocess
import sys
import tempfile
import zipfile

zip_path, platform, source = sys.argv[1:4]
failures = []


def check(cond, what):
    if not cond:
        failures.append(what)


version = re.search(r"project\(firmament VERSION ([0-9.]+) ", open(os.path.join(source, "CMakeLists.txt")).read())[1]
check(os.path.basename(zip_path) == f"firmament_sky-{version}-{platform.replace('-', '_')}.zip",
      f"zip name {os.path.basename(zip_path)} does not carry version {version} and platform {platform}")
z = zipfile.ZipFile(zip_path)
names = set(z.namelist())
manifest = z.read("firmament_sky/blender_manifest.toml").decode()
check(re.search(r'(?m)^version = "%s"$' % re.escape(version), manifest), f"manifest version is not {version}")
check(re.findall(r"(?m)^platforms = (.*)$", manifest) == [f'["{platform}"]'],
      f"manifest platforms: {re.findall(r'(?m)^platforms = .*$', manifest)}, expected [\"{platform}\"]")
init = z.read("firmament_sky/__init__.py").decode()
check('"version": (%s)' % ", ".join(version.split(".")) in init, f"bl_info version is not {version}")

exe = "firmament_sky/bin/" + ("firmament.exe" if platform.startswith("windows") else "firmament")
check(exe in names, f"{exe} missing")
if exe in names:
    check((z.getinfo(exe).external_attr >> 16) & 0o111 == 0o111, f"{exe} is not executable (mode in the zip)")
for d in ("biomes", "clouds", "skies", "atmospheres"):
    want = sorted(f for f in os.listdir(os.path.join(source, "presets", d)) if f.endswith(".json"))
    have = sorted(n.rsplit("/", 1)[1] for n in names if n.startswith(f"firmament_sky/presets/{d}/") and n.endswith(".json"))
    check(have == want, f"presets/{d}: {have}, expected {want}")
check("firmament_sky/presets/ocio/config.ocio" in names, "the OpenColorIO config is missing")

if platform == "linux-x64" and exe in names:
    base = {l.strip() for l in open(os.path.join(source, "scripts", "linux-base-libs")) if l.strip() and not l.startswith("#")}
    with tempfile.TemporaryDirectory() as tmp:
        bundled = sorted(n for n in names if n.startswith("firmament_sky/bin/lib/") and not n.endswith("/"))
        for n in [exe] + bundled:
            z.extract(n, tmp)
        for n in [exe] + bundled:
            dyn = subprocess.run(["readelf", "-d", os.path.join(tmp, n)], capture_output=True, text=True, check=True).stdout
            runpath = re.findall(r"\((?:RUNPATH|RPATH)\).*\[(.*)\]", dyn)
            check(runpath == (["$ORIGIN/lib"] if n == exe else ["$ORIGIN"]), f"{n}: runpath {runpath}")
            for need in re.findall(r"\(NEEDED\).*\[(.*)\]", dyn):
                check(need in base or f"firmament_sky/bin/lib/{need}" in names,
                      f"{n} needs {need}: neither bundled in bin/lib nor in the base system")
        for n in bundled:
            check(os.path.basename(n) not in base, f"{n} is a base system library and must not be bundled")
        check(any("libOpenColorIO" in n for n in bundled), "OpenColorIO is not bundled")
        # the oldest base system named (Ubuntu 22.04): glibc 2.35, libstdc++ of GCC 12 (GLIBCXX_3.4.30)
        newest = {"GLIBC": (2, 35), "GLIBCXX": (3, 4, 30)}
        for n in [exe] + bundled:
            syms = subprocess.run(["objdump", "-T", os.path.join(tmp, n)], capture_output=True, text=True, check=True).stdout
            for lib, ver in set(re.findall(r"\b(GLIBC|GLIBCXX)_([0-9.]+)\b", syms)):
                check(tuple(map(int, ver.split("."))) <= newest[lib], f"{n} needs {lib}_{ver}, newer than Ubuntu 22.04's")
        expat = os.path.join(tmp, "firmament_sky/bin/lib/libexpat.so.1")
        if os.path.exists(expat):  # the relinked one (scripts/package) parses XML
            import ctypes
            lib = ctypes.CDLL(expat)
            lib.XML_ParserCreate.restype = ctypes.c_void_p
            lib.XML_Parse.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_int, ctypes.c_int]
            lib.XML_ParserFree.argtypes = [ctypes.c_void_p]
            parser = lib.XML_ParserCreate(None)
            doc = b'<ProcessList id="x"><Matrix/></ProcessList>'
            check(parser and lib.XML_Parse(parser, doc, len(doc), 1) == 1, "the bundled libexpat does not parse XML")
            bad = lib.XML_ParserCreate(None)
            check(lib.XML_Parse(bad, b"<a><b></a>", 10, 1) == 0, "the bundled libexpat accepts malformed XML")
            lib.XML_ParserFree(parser)
            lib.XML_ParserFree(bad)

# Windows: every DLL the executable imports is one that every Windows has, or bundled beside it
# (the build links its libraries and runtimes statically: scripts/package-windows.sh).
WINDOWS_DLLS = {"kernel32.dll", "msvcrt.dll", "shell32.dll", "user32.dll", "advapi32.dll", "ws2_32.dll", "ole32.dll"}
if platform == "windows-x64" and exe in names:
    with tempfile.TemporaryDirectory() as tmp:
        z.extract(exe, tmp)
        dump = subprocess.run(["x86_64-w64-mingw32-objdump", "-p", os.path.join(tmp, exe)], capture_output=True,
                              text=True, check=True).stdout
        check("file format pei-x86-64" in dump, f"{exe} is not a Windows x64 executable")
        for dll in re.findall(r"DLL Name: (\S+)", dump):
            check(dll.lower() in WINDOWS_DLLS or f"firmament_sky/bin/{dll}" in names,
                  f"{exe} imports {dll}: neither a Windows system DLL nor bundled in bin/")

for f in failures:
    print("FAIL:", f)
print(f"{os.path.basename(zip_path)}: {len(names)} files, {os.path.getsize(zip_path) / 1e6:.1f} MB, "
      f"{len(failures)} failures")
sys.exit(1 if failures else 0)
