# Renders an emboss studio export (emboss export --format studio) with Blender's Cycles path tracer:
# the exported mesh, lit by the same environment, seen by the same camera, the metal's reflectance
# from the same measured n and k through the exact conductor Fresnel term, GGX of the same alpha
# (multiple scattering GGX), and the same tone curve. Run by metal-reference.sh:
#   blender -b --factory-startup -P cycles_reference.py -- STUDIO.json MESH.stl OUT.png WxH SAMPLES [OURS.png]
# With OURS.png (emboss render of the same scene and size), OUT.png is the two side by side:
# emboss on the left, Cycles on the right.
import cmath
import json
import math
import os
import sys

import bpy
from mathutils import Matrix, Vector

args = sys.argv[sys.argv.index("--") + 1:]
studio_path, mesh_path, out_path, size, samples = args[0], args[1], args[2], args[3], int(args[4])
ours_path = args[5] if len(args) > 5 else None
width, height = (int(v) for v in size.lower().split("x"))
studio = json.load(open(studio_path))
metal = studio["metal"]

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.max_bounces = 12
scene.cycles.glossy_bounces = 12
scene.cycles.caustics_reflective = True
scene.cycles.blur_glossy = 0.0
scene.cycles.seed = 1
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
scene.render.threads_mode = "FIXED"
scene.render.threads = os.cpu_count() or 2
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
scene.display_settings.display_device = "sRGB"
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_depth = "8"

# ---- the piece: the exported STL, in mm, smooth shaded except at creases
bpy.ops.preferences.addon_enable(module="io_mesh_stl")
bpy.ops.import_mesh.stl(filepath=mesh_path, global_scale=1.0, axis_forward="Y", axis_up="Z")
piece = bpy.context.selected_objects[0]
piece.data.polygons.foreach_set("use_smooth", [True] * len(piece.data.polygons))
piece.data.use_auto_smooth = True
piece.data.auto_smooth_angle = math.radians(35.0)


def fresh_nodes(owner):
    """The node tree of a material, world or scene, emptied: its nodes and links."""
    owner.use_nodes = True
    tree = owner.node_tree
    tree.nodes.clear()
    return tree.nodes, tree.links


def fresnel_conductor(cos_i, n, k):
    """Unpolarised reflectance of n + ik from the complex Fresnel amplitudes (Born and Wolf)."""
    N = complex(n, k)
    sin2 = 1.0 - cos_i * cos_i
    cos_t = cmath.sqrt(1.0 - sin2 / (N * N))
    rs = (cos_i - N * cos_t) / (cos_i + N * cos_t)
    rp = (N * cos_i - cos_t) / (N * cos_i + cos_t)
    return 0.5 * (abs(rs) ** 2 + abs(rp) ** 2)


# The Fresnel curve of the metal as a 1024 x 1 float texture, looked up by the cosine of the angle
# between the shading normal and the incoming ray.
bins = 1024
table = bpy.data.images.new("fresnel", bins, 1, alpha=True, float_buffer=True)
table.colorspace_settings.name = "Non-Color"
pixels = []
for i in range(bins):
    mu = max(1e-4, (i + 0.5) / bins)
    pixels += [fresnel_conductor(mu, metal["eta"][c], metal["k"][c]) for c in range(3)] + [1.0]
table.pixels = pixels
table.pack()

mat = bpy.data.materials.new("metal")
nodes, links = fresh_nodes(mat)
out = nodes.new("ShaderNodeOutputMaterial")
glossy = nodes.new("ShaderNodeBsdfGlossy")
glossy.distribution = "MULTI_GGX"
glossy.inputs["Roughness"].default_value = math.sqrt(metal["roughness_alpha"])  # Cycles: alpha = roughness^2
facing = nodes.new("ShaderNodeLayerWeight")  # Facing = 1 - |N.I| at blend 0.5
facing.inputs["Blend"].default_value = 0.5
cosine = nodes.new("ShaderNodeMath")
cosine.operation = "SUBTRACT"
cosine.inputs[0].default_value = 1.0
links.new(facing.outputs["Facing"], cosine.inputs[1])
uv = nodes.new("ShaderNodeCombineXYZ")
uv.inputs["Y"].default_value = 0.5
links.new(cosine.outputs[0], uv.inputs["X"])
tex = nodes.new("ShaderNodeTexImage")
tex.image = table
tex.interpolation = "Linear"
tex.extension = "EXTEND"
links.new(uv.outputs[0], tex.inputs["Vector"])
links.new(tex.outputs["Color"], glossy.inputs["Color"])
links.new(glossy.outputs[0], out.inputs["Surface"])
piece.data.materials.append(mat)

# ---- the studio: the exported environment; camera rays that miss see the backdrop's colour
world = bpy.data.worlds.new("studio")
scene.world = world
wn, wl = fresh_nodes(world)
wout = wn.new("ShaderNodeOutputWorld")
env = wn.new("ShaderNodeTexEnvironment")
env.image = bpy.data.images.load(os.path.join(os.path.dirname(os.path.abspath(studio_path)), studio["environment"]))
env.projection = "EQUIRECTANGULAR"
env.interpolation = "Linear"
bg = wn.new("ShaderNodeBackground")
wl.new(env.outputs["Color"], bg.inputs["Color"])
backdrop = wn.new("ShaderNodeBackground")
backdrop.inputs["Color"].default_value = (0.014, 0.016, 0.021, 1.0)
path = wn.new("ShaderNodeLightPath")
mix = wn.new("ShaderNodeMixShader")
wl.new(path.outputs["Is Camera Ray"], mix.inputs["Fac"])
wl.new(bg.outputs[0], mix.inputs[1])
wl.new(backdrop.outputs[0], mix.inputs[2])
wl.new(mix.outputs[0], wout.inputs["Surface"])
world.cycles.sample_map_resolution = 2048

# ---- the camera
cam_spec = studio["camera"]
cam_data = bpy.data.cameras.new("camera")
cam_data.clip_start, cam_data.clip_end = 1.0, 10000.0
if cam_spec["type"] == "perspective":
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(cam_spec["fov_deg"])
else:
    cam_data.type = "ORTHO"
    cam_data.sensor_fit = "VERTICAL"
    cam_data.ortho_scale = cam_spec["height"]
cam = bpy.data.objects.new("camera", cam_data)
scene.collection.objects.link(cam)
eye, target, up = Vector(cam_spec["eye"]), Vector(cam_spec["target"]), Vector(cam_spec["up"])
forward = (target - eye).normalized()
right = forward.cross(up).normalized()
cam_up = right.cross(forward)
rot = Matrix((right, cam_up, -forward)).transposed()
cam.matrix_world = Matrix.Translation(eye) @ rot.to_4x4()
scene.camera = cam

# ---- the tone curve: c^2 / (c + 0.03), then c / (1 + 0.25 c), per channel before the sRGB curve
# (the Standard view): emboss's toSrgb8()
cn, cl = fresh_nodes(scene)
layers = cn.new("CompositorNodeRLayers")
split = cn.new("CompositorNodeSeparateColor")
join = cn.new("CompositorNodeCombineColor")
cl.new(layers.outputs["Image"], split.inputs[0])


def math_node(op, a, b=None, value=None):
    node = cn.new("CompositorNodeMath")
    node.operation = op
    cl.new(a, node.inputs[0])
    if b is not None:
        cl.new(b, node.inputs[1])
    else:
        node.inputs[1].default_value = value
    return node.outputs[0]


for i in range(3):
    c = math_node("MAXIMUM", split.outputs[i], value=0.0)
    toe = math_node("DIVIDE", math_node("MULTIPLY", c, c), math_node("ADD", c, value=0.03))
    denom = cn.new("CompositorNodeMath")
    denom.operation = "MULTIPLY_ADD"
    denom.inputs[1].default_value = 0.25
    denom.inputs[2].default_value = 1.0
    cl.new(toe, denom.inputs[0])
    cl.new(math_node("DIVIDE", toe, denom.outputs[0]), join.inputs[i])
composite = cn.new("CompositorNodeComposite")
cl.new(join.outputs[0], composite.inputs["Image"])

cycles_path = out_path if ours_path is None else out_path + ".cycles.png"
scene.render.filepath = cycles_path
bpy.ops.render.render(write_still=True)
if ours_path is not None:
    # Side by side, 8 pixels of backdrop between: emboss | Cycles.
    ours = bpy.data.images.load(ours_path)
    theirs = bpy.data.images.load(cycles_path)
    if tuple(ours.size) != (width, height):
        sys.exit("cycles_reference: %s is %dx%d, not %dx%d" % (ours_path, ours.size[0], ours.size[1], width, height))
    gap = 8
    side = bpy.data.images.new("side", 2 * width + gap, height, alpha=False)
    side.colorspace_settings.name = "sRGB"
    a, b = list(ours.pixels), list(theirs.pixels)
    fill = [0.014, 0.016, 0.021, 1.0] * gap
    rows = []
    for y in range(height):
        rows += a[4 * width * y:4 * width * (y + 1)] + fill + b[4 * width * y:4 * width * (y + 1)]
    side.pixels = rows
    side.filepath_raw = out_path
    side.file_format = "PNG"
    side.save()
    os.remove(cycles_path)
print("cycles_reference: wrote", out_path)
