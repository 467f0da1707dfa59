# Imports a rigged hand (.glb, e.g. from `prehensile export-hand`) into Blender, headless, and
# prints what Blender made of it as one line of JSON after the marker "RIG_JSON ":
#   blender -b -P tools/import_rig_in_blender.py -- hand.glb
# {"armatures": [{"name", "bones": [{"name", "parent", "head"}]}],
#  "meshes": [{"name", "vertices", "polygons", "min", "max", "armature", "groups",
#              "deformed_max"}]}
# Positions are Blender's world coordinates (Z-up, m): bone heads at rest, the mesh's bounding
# box at rest. "deformed_max" is the largest distance a vertex moves when the armature's
# every bone is turned 20° about its own x axis: the armature deforms the mesh when it is > 0.
# (Debian's Blender 3.4; tests/hand_rig_export.rs runs it when `blender` is on PATH.)
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # Debian Blender 3.4 with numpy >= 1.24
import bpy, sys, json, math
argv = sys.argv[sys.argv.index("--") + 1:]
path = argv[0]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
scene = bpy.context.scene
out = {"armatures": [], "meshes": []}
armatures = [o for o in scene.objects if o.type == 'ARMATURE']
for a in armatures:
    bones = [{"name": b.name,
              "parent": b.parent.name if b.parent else None,
              "head": list(a.matrix_world @ b.head_local)} for b in a.data.bones]
    out["armatures"].append({"name": a.name, "bones": bones})
deps = bpy.context.evaluated_depsgraph_get()
def world_vertices(o):
    e = o.evaluated_get(bpy.context.evaluated_depsgraph_get())
    m = e.to_mesh()
    v = [o.matrix_world @ x.co for x in m.vertices]
    e.to_mesh_clear()
    return v
rest = {o.name: world_vertices(o) for o in scene.objects if o.type == 'MESH'}
# Turn every bone 20° about its x axis and measure how far the skin moves.
for a in armatures:
    for pb in a.pose.bones:
        pb.rotation_mode = 'XYZ'
        pb.rotation_euler = (math.radians(20), 0, 0)
bpy.context.view_layer.update()
for o in scene.objects:
    if o.type != 'MESH':
        continue
    v = rest[o.name]
    posed = world_vertices(o)
    mods = [m for m in o.modifiers if m.type == 'ARMATURE']
    out["meshes"].append({
        "name": o.name,
        "vertices": len(o.data.vertices),
        "polygons": len(o.data.polygons),
        "min": [min(p[i] for p in v) for i in range(3)],
        "max": [max(p[i] for p in v) for i in range(3)],
        "armature": mods[0].object.name if mods and mods[0].object else None,
        "groups": [g.name for g in o.vertex_groups],
        "deformed_max": max((p - q).length for p, q in zip(posed, v)),
    })
print("RIG_JSON " + json.dumps(out))
