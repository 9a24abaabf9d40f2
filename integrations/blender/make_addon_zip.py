"""Makes the Blender add-on's installable zip: the add-on plus the pure-Python koma package.

Usage: make_addon_zip.py ADDON_DIR KOMA_PACKAGE_DIR VERSION OUT_ZIP
  ADDON_DIR          integrations/blender/koma_retime
  KOMA_PACKAGE_DIR   the assembled package (build/python/koma: sources and generated stubs)
  VERSION            the project's version; the add-on's bl_info["version"] must equal it
The zip holds koma_retime/__init__.py and koma_retime/bundled/koma/... (every .py), which the
add-on imports when no other koma is configured, so only grpcio (and protobuf) must come from
Blender's Python. Entries are sorted and dated 1980-01-01: the same inputs make the same bytes.
"""
import ast
import os
import sys
import zipfile

EPOCH = (1980, 1, 1, 0, 0, 0)


def addon_version(init_py):
    for node in ast.walk(ast.parse(open(init_py).read())):
        if isinstance(node, ast.Assign) and any(
                isinstance(t, ast.Name) and t.id == "bl_info" for t in node.targets):
            return ".".join(map(str, ast.literal_eval(node.value)["version"]))
    sys.exit(f"{init_py}: no bl_info")


def main():
    addon_dir, package_dir, version, out_zip = sys.argv[1:5]
    init_py = os.path.join(addon_dir, "__init__.py")
    if addon_version(init_py) != version:
        sys.exit(f"{init_py}: bl_info version {addon_version(init_py)} is not the project's "
                 f"{version} (CMakeLists.txt project())")
    entries = {"koma_retime/__init__.py": init_py}
    for folder, dirs, names in os.walk(package_dir):
        dirs[:] = sorted(d for d in dirs if d != "__pycache__")
        for name in names:
            if name.endswith(".py"):
                path = os.path.join(folder, name)
                relative = os.path.relpath(path, package_dir).replace(os.sep, "/")
                entries["koma_retime/bundled/koma/" + relative] = path
    if "koma_retime/bundled/koma/v1/retime_pb2_grpc.py" not in entries:
        sys.exit(f"{package_dir}: no generated stubs (build the koma_python target)")
    os.makedirs(os.path.dirname(os.path.abspath(out_zip)), exist_ok=True)
    partial = out_zip + ".tmp"
    with zipfile.ZipFile(partial, "w", zipfile.ZIP_DEFLATED) as archive:
        for name in sorted(entries):
            info = zipfile.ZipInfo(name, EPOCH)
            info.compress_type = zipfile.ZIP_DEFLATED
            info.external_attr = 0o644 << 16
            with open(entries[name], "rb") as f:
                archive.writestr(info, f.read())
    os.replace(partial, out_zip)
    print(f"{out_zip}: {len(entries)} files")


if __name__ == "__main__":
    main()
