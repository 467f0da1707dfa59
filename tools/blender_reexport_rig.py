"""Re-export a rigged glTF through Blender's own importer and exporter, as an animator's round trip
would: `blender -b --python tools/blender_reexport_rig.py -- in.glb out.gltf GLTF_EMBEDDED|GLB`.
Made the fixtures tests/fixtures/blender-*.gl* (from `prehensile export-hand --form simple`,
the simple form), which
tests/hand_import.rs reads as Blender's output."""
import bpy, sys
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool
argv = sys.argv[sys.argv.index("--") + 1:]
src, dst, fmt = argv
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src)
bpy.ops.export_scene.gltf(filepath=dst, export_format=fmt, export_skins=True, export_animations=False)
print("EXPORTED", dst)
