"""Where the maps live.  A saved .blend keeps its maps beside it, in //firmament/<folder>/, referenced
by paths relative to the .blend (the project can move); an unsaved file writes them to the add-on's
user folder (the cache), and saving copies them beside the .blend.  Nothing here deletes a map
on its own: a map a saved file may use stays until "Clean Unused Maps" (an explicit action)."""

import os
import shutil
import uuid

import bpy

TAG = "firmament_sky"  # the custom property of the add-on's images (world.TAG)
FOLDER = "firmament"  # beside the .blend


def cache_dir():
    """The maps of unsaved files: the extension's user folder (4.2+) or the user data folder."""
    try:
        base = bpy.utils.extension_path_user(__package__, create=True)
    except (AttributeError, ValueError):
        base = bpy.utils.user_resource("DATAFILES", path="firmament_sky", create=True)
    path = os.path.join(base, "skies")
    os.makedirs(path, exist_ok=True)
    return path


def maps_root(blend_path=None):
    """//firmament/ of the saved .blend (blend_path, default the open file's), else the cache."""
    blend = bpy.data.filepath if blend_path is None else blend_path
    if blend:
        return os.path.join(os.path.dirname(os.path.abspath(blend)), FOLDER)
    return cache_dir()


def new_folder():
    """A fresh folder for one generation, in maps_root()."""
    root = maps_root()
    os.makedirs(root, exist_ok=True)
    path = os.path.join(root, uuid.uuid4().hex[:12])
    os.makedirs(path)
    return path


def our_images():
    return [img for img in bpy.data.images if img.get(TAG) and img.source in ("FILE", "SEQUENCE")]


def reference(img, path):
    """Points img at path: relative to the .blend when the file is saved (//firmament/...)."""
    if bpy.data.filepath:
        try:
            path = bpy.path.relpath(path)
        except ValueError:  # another drive (Windows)
            pass
    if img.filepath != path:
        img.filepath = path


def keep_with_blend(blend_path):
    """Copies every map of this file that lives outside blend_path's //firmament/ (in the cache, or
    beside another .blend after Save As) into it and points the images there by relative paths.
    Returns the number of folders copied."""
    root = maps_root(blend_path)
    copied = 0
    for img in our_images():
        if img.packed_file is not None:
            continue
        src = bpy.path.abspath(img.filepath)
        folder = os.path.dirname(src)
        if os.path.dirname(folder) == root:
            continue
        dst = os.path.join(root, os.path.basename(folder))
        if not os.path.isdir(dst) and os.path.isdir(folder):
            os.makedirs(root, exist_ok=True)
            shutil.copytree(folder, dst + ".tmp")
            os.replace(dst + ".tmp", dst)
            copied += 1
        if os.path.isdir(dst):
            img.filepath = os.path.join(dst, os.path.basename(src))
    return copied


_saving = {"again": False}


@bpy.app.handlers.persistent
def on_save_post(*_args):
    """After a save: bring the maps beside the .blend with relative paths, and write the file once
    more when that changed any path (Blender 3.4's save_pre does not say where the file goes)."""
    if _saving["again"] or not bpy.data.filepath:
        return
    scenes = [s for s in bpy.data.scenes if getattr(s, "firmament_sky", None) is not None]
    if scenes and not all(s.firmament_sky.keep_maps_with_file for s in scenes):
        return
    before = [img.filepath for img in our_images()]
    keep_with_blend(bpy.data.filepath)
    for img in our_images():
        if img.packed_file is None:
            reference(img, bpy.path.abspath(img.filepath))
    if [img.filepath for img in our_images()] != before:
        _saving["again"] = True
        try:
            bpy.ops.wm.save_mainfile(filepath=bpy.data.filepath, check_existing=False)
        finally:
            _saving["again"] = False


def folder_size(path):
    total = 0
    for dirpath, _dirs, files in os.walk(path):
        for f in files:
            try:
                total += os.path.getsize(os.path.join(dirpath, f))
            except OSError:
                pass
    return total


def _used_folders():
    return {os.path.dirname(os.path.abspath(bpy.path.abspath(img.filepath))) for img in our_images()}


def _used_by_other_blends(root, name):
    """Whether a .blend beside root (other than the open one) may use map folder `name`: its bytes
    hold the name, or it is compressed (cannot tell: assume it does)."""
    parent = os.path.dirname(root)
    for f in os.listdir(parent):
        path = os.path.join(parent, f)
        if not f.endswith(".blend") or os.path.abspath(path) == os.path.abspath(bpy.data.filepath or ""):
            continue
        try:
            with open(path, "rb") as fh:
                data = fh.read()
        except OSError:
            return True
        if not data.startswith(b"BLENDER") or name.encode() in data:
            return True
    return False


def unused():
    """[(folder, bytes)] that Clean Unused Maps removes: folders of the cache and of //firmament/ that
    this file does not use and (beside the .blend) no other .blend of its folder names."""
    used = _used_folders()
    found = []
    roots = [cache_dir()] + ([maps_root()] if bpy.data.filepath else [])
    for root in roots:
        if not os.path.isdir(root):
            continue
        for name in sorted(os.listdir(root)):
            path = os.path.join(root, name)
            if not os.path.isdir(path) or path in used:
                continue
            if root != cache_dir() and _used_by_other_blends(root, name):
                continue
            found.append((path, folder_size(path)))
    return found


def summary():
    """One line: where the maps are and how much they take."""
    roots = [maps_root()] if bpy.data.filepath else []
    roots.append(cache_dir())
    parts = []
    for root in roots:
        n = len(os.listdir(root)) if os.path.isdir(root) else 0
        size = folder_size(root) if os.path.isdir(root) else 0
        parts.append("%s: %d maps, %.1f MB" % (root, n, size / 1e6))
    return "; ".join(parts)
