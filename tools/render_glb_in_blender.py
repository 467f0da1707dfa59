# Renders the last frame of an animation.glb written by `prehensile solve` in Blender, headless:
#   blender -b -P tools/render_glb_in_blender.py -- DIR/animation.glb out.png
# (Debian's Blender 3.4; Cycles on the CPU.) The image docs/images/blender-animation-glb.png was
# made so from assets/scenes/hand-grasp-ball.toml.
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # Debian Blender 3.4 with numpy >= 1.24
import bpy, sys, mathutils
argv = sys.argv[sys.argv.index("--") + 1:]
path, out = argv[0], argv[1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
scene = bpy.context.scene
meshes = [o for o in scene.objects if o.type == 'MESH']
print("imported", len(meshes), "meshes;", [o.name for o in meshes][:5])
keyed = [o for o in meshes if o.data.shape_keys]
print("with shape keys:", len(keyed), "keys on first:", len(keyed[0].data.shape_keys.key_blocks) if keyed else 0)
# The last frame of the animation.
end = 0
for a in bpy.data.actions:
    end = max(end, a.frame_range[1])
scene.frame_set(int(round(end)))
print("frame", scene.frame_current, "of", end)
# Materials: skin, bone, and the ball coloured by its pressure (COLOR_0).
def material(name, rgba, attribute=None):
    m = bpy.data.materials.new(name); m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]; bsdf.inputs["Base Color"].default_value = rgba
    if attribute:
        a = m.node_tree.nodes.new("ShaderNodeVertexColor"); a.layer_name = attribute
        m.node_tree.links.new(a.outputs["Color"], bsdf.inputs["Base Color"])
    return m
skin = material("skin", (0.85, 0.62, 0.52, 1)); bone = material("bone", (0.95, 0.93, 0.85, 1))
for o in meshes:
    if o.name.endswith("_skin"):
        o.data.materials.append(skin)
    elif o.name.startswith("hand_"):
        o.data.materials.append(bone)
    else:
        attrs = [a.name for a in o.data.color_attributes]
        o.data.materials.append(material("pressure", (0.3, 0.4, 0.9, 1), attrs[0] if attrs else None))
# Frame everything.
lo = mathutils.Vector((1e9,)*3); hi = mathutils.Vector((-1e9,)*3)
deps = bpy.context.evaluated_depsgraph_get()
for o in meshes:
    for c in o.bound_box:
        w = o.matrix_world @ mathutils.Vector(c)
        lo = mathutils.Vector(map(min, lo, w)); hi = mathutils.Vector(map(max, hi, w))
centre = (lo + hi) / 2; size = (hi - lo).length
cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam")); scene.collection.objects.link(cam)
cam.location = centre + mathutils.Vector((0.35, -1.0, 0.6)).normalized() * size * 1.6
cam.rotation_euler = (centre - cam.location).to_track_quat('-Z', 'Y').to_euler()
scene.camera = cam
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN')); sun.data.energy = 4
sun.rotation_euler = (0.6, 0.2, 0.8); scene.collection.objects.link(sun)
world = bpy.data.worlds.new("w"); world.color = (0.9, 0.9, 0.92); scene.world = world
scene.render.engine = 'CYCLES'; scene.cycles.device = 'CPU'; scene.cycles.samples = 24; scene.cycles.use_denoising = False
scene.render.resolution_x = 960; scene.render.resolution_y = 600; scene.render.film_transparent = False
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print("rendered", out)
