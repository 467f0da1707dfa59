# Renders a rigged hand (.glb, e.g. from `prehensile export-hand`) in Blender, headless, as
# imported: the armature posed (every finger bone flexed by an angle about the hand's lateral
# axis, the thumb's by half of it) deforming the skin, shown through the half-transparent skin
# as sticks from joint to joint:
#   blender -b -P tools/render_rig_in_blender.py -- hand.glb out.png [flexion_degrees=30]
# (Debian's Blender 3.4; the Workbench engine on the CPU.) docs/images/hand-rig-export-blender.png
# was made so from `prehensile export-hand --out hand.glb --open-wrist`.
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # Debian Blender 3.4 with numpy >= 1.24
import bpy, sys, math, mathutils
argv = sys.argv[sys.argv.index("--") + 1:]
path, out = argv[0], argv[1]
flexion = math.radians(float(argv[2])) if len(argv) > 2 else math.radians(30)
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=path)
scene = bpy.context.scene
arm = next(o for o in scene.objects if o.type == 'ARMATURE')
skin = next(o for o in scene.objects if o.type == 'MESH')
print("armature", arm.name, len(arm.data.bones), "bones; mesh", skin.name, len(skin.data.vertices), "vertices")
# Flexion: a rotation about the hand's lateral axis (world +y for a right hand, −y for a left:
# the fingertips go palmar, −z), in each bone's rest frame.
left = any(b.name.lower().endswith(("_l", ".l")) or "left" in b.name.lower() for b in arm.data.bones)
lateral = mathutils.Vector((0, -1 if left else 1, 0))
axis = (arm.matrix_world.to_3x3().inverted() @ lateral).normalized()
for pb in arm.pose.bones:
    if pb.parent is None:
        continue  # the wrist
    thumb = "thumb" in pb.name.lower() or "finger1" in pb.name.lower()
    angle = flexion * (0.5 if thumb else 1.0)
    rest = pb.bone.matrix_local.to_quaternion()
    pb.rotation_mode = 'QUATERNION'
    pb.rotation_quaternion = rest.inverted() @ mathutils.Quaternion(axis, angle) @ rest
bpy.context.view_layer.update()
# A stick per bone as posed
def stick(name, head, tail, radius):
    d = tail - head
    bpy.ops.mesh.primitive_cone_add(vertices=12, radius1=radius, radius2=radius * 0.4,
                                    depth=d.length, location=(head + tail) / 2)
    o = bpy.context.active_object
    o.name = name
    o.rotation_euler = d.to_track_quat('Z', 'Y').to_euler()
    o.color = (0.15, 0.25, 0.85, 1)
    return o
# (joint to joint: to each child's head; a bone without children to its own tail)
for pb in arm.pose.bones:
    head = arm.matrix_world @ pb.head
    ends = [arm.matrix_world @ c.head for c in pb.children] or [arm.matrix_world @ pb.tail]
    for end in ends:
        stick("bone " + pb.name, head, end, 0.0015)
skin.color = (0.9, 0.62, 0.5, 1)
# Frame the hand from above its back, from the wrist and the thumb's side.
lo = mathutils.Vector((1e9,) * 3); hi = mathutils.Vector((-1e9,) * 3)
for c in skin.bound_box:
    w = skin.matrix_world @ mathutils.Vector(c)
    lo = mathutils.Vector(map(min, lo, w)); hi = mathutils.Vector(map(max, hi, w))
centre = (lo + hi) / 2; size = (hi - lo).length
cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam")); scene.collection.objects.link(cam)
cam.location = centre + mathutils.Vector((-0.3, 0.6 if not left else -0.6, 1.0)).normalized() * size * 1.6
cam.rotation_euler = (centre - cam.location).to_track_quat('-Z', 'Y').to_euler()
scene.camera = cam
scene.render.engine = 'BLENDER_WORKBENCH'
shading = scene.display.shading
shading.light = 'STUDIO'; shading.color_type = 'OBJECT'
shading.show_xray = True; shading.xray_alpha = 0.55
world = bpy.data.worlds.new("w"); world.color = (0.93, 0.93, 0.95); scene.world = world
scene.render.resolution_x = 960; scene.render.resolution_y = 640
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print("rendered", out)
