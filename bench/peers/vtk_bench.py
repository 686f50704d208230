#!/usr/bin/env python3
"""VTK's ray casters on the engine views that svr_raycast_peer_bench times for ours: the CPU one
(--mapper fixedpoint: vtkFixedPointVolumeRayCastMapper, what ParaView uses without a GPU)
against our raycast backend, and the OpenGL one (--mapper gpu: vtkGPUVolumeRayCastMapper, on
the X server's GL, Mesa's llvmpipe under Xvfb here) against our gl.mode=raycast.

Everything comes from `svr_raycast_peer_bench --export=PREFIX` (PREFIX.json, PREFIX.raw): the
voxels, the opacity per unit length and the rgb reflectance at each of the 256 values, the
shading, the light direction and each azimuth's orthographic camera. Matched: sample distance
(our step, 0.5 voxel; automatic adjustment off), image sample distance 1 (one ray per pixel),
image size, thread count, opacity (ScalarOpacityUnitDistance 1 = our per-unit-length opacity),
Phong ambient/diffuse/shininess and a directional light. Not matched: VTK has one specular
coefficient for the whole volume (we weight the highlight per material: it is set to the
scene's specular × the largest specular weight), its colour and opacity are looked up after
interpolating the value as ours are, but with 15-bit fixed-point compositing and gradients
precomputed per voxel (quantised normals) where we interpolate precomputed gradients; its
early termination threshold is built in: a ray stops once its 15-bit accumulated opacity
passes 32512/32767, a remaining transmittance of about 0.0078 (ours: the scene's 0.01).

Time per frame: for the fixed-point mapper its own GetTimeToDraw(), which covers the ray casting
and the blit of its image into the window; for the GPU mapper the wall time of Render() (GL
runs asynchronously, so only a finished frame counts: llvmpipe finishes it at the buffer swap),
which our GlRaycast rows match by including the read-back. The wall time of the whole Render()
is recorded for both. The GPU mapper's sample distance is matched as the CPU one's; its
gradients come from its own shader (central differences), its opacity is corrected for the
sample distance as ours. VTK needs an X display here
(Debian's VTK 9.1 has no OSMesa or EGL window): bench/peers/run starts this under xvfb-run.

  python3 bench/peers/vtk_bench.py --scene out/peers/engine --threads 1 --json vtk.json
"""
import argparse
import json
import sys
import time

import numpy as np

try:
    import vtk
    from vtk.util import numpy_support
except ImportError:
    sys.exit("vtk_bench: VTK's Python module is missing; install it with ./setup.sh --peers "
             "(Debian python3-vtk9)")


def image_data(scene, prefix):
    dims = scene["dims"]
    voxels = np.fromfile(prefix + ".raw", dtype=np.uint8)
    if voxels.size != dims[0] * dims[1] * dims[2]:
        sys.exit(f"vtk_bench: {prefix}.raw holds {voxels.size} voxels, expected {dims}")
    img = vtk.vtkImageData()
    img.SetDimensions(*dims)
    img.SetSpacing(*scene["spacing"])
    # Centred at the origin, as our world space is (volume.h).
    img.SetOrigin(*[-0.5 * (d - 1) * s for d, s in zip(dims, scene["spacing"])])
    arr = numpy_support.numpy_to_vtk(voxels, deep=True, array_type=vtk.VTK_UNSIGNED_CHAR)
    img.GetPointData().SetScalars(arr)
    return img


def volume_property(scene):
    opacity = vtk.vtkPiecewiseFunction()
    colour = vtk.vtkColorTransferFunction()
    for v, (a, rgb) in enumerate(zip(scene["opacity_per_unit_length"], scene["rgb"])):
        opacity.AddPoint(v, a)
        colour.AddRGBPoint(v, *(min(max(c, 0.0), 1.0) for c in rgb))
    prop = vtk.vtkVolumeProperty()
    prop.SetScalarOpacity(opacity)
    prop.SetColor(colour)
    prop.SetScalarOpacityUnitDistance(1.0)
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOn()
    sh = scene["shading"]
    prop.SetAmbient(sh["ambient"])
    prop.SetDiffuse(sh["diffuse"])
    prop.SetSpecular(sh["specular"] * max(scene["specular_weight"]))
    prop.SetSpecularPower(sh["shininess"])
    return prop


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", required=True, help="PREFIX written by svr_raycast_peer_bench --export")
    ap.add_argument("--sizes", default="512,800")
    ap.add_argument("--views", help="azimuths to time, e.g. -60,44 (default: every exported one)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--mapper", choices=["fixedpoint", "gpu"], default="fixedpoint")
    ap.add_argument("--frames", type=int, default=5, help="timed frames per view (after one warm-up)")
    ap.add_argument("--json", required=True, help="output: one record per view and size")
    ap.add_argument("--png", help="write each view's image to PNG files with this prefix")
    args = ap.parse_args()

    scene = json.load(open(args.scene + ".json"))
    if args.mapper == "gpu":
        mapper = vtk.vtkOpenGLGPUVolumeRayCastMapper()
        mapper.AutoAdjustSampleDistancesOff()
        mapper.LockSampleDistanceToInputSpacingOff()
        mapper.SetSampleDistance(scene["step_world"])
        mapper.SetImageSampleDistance(1.0)
        mapper.SetMaxMemoryInBytes(2 << 30)
    else:
        mapper = vtk.vtkFixedPointVolumeRayCastMapper()
        mapper.SetNumberOfThreads(args.threads)
        mapper.AutoAdjustSampleDistancesOff()
        mapper.SetSampleDistance(scene["step_world"])
        mapper.SetInteractiveSampleDistance(scene["step_world"])
        mapper.SetImageSampleDistance(1.0)
        mapper.SetMinimumImageSampleDistance(1.0)
        mapper.SetMaximumImageSampleDistance(1.0)
    mapper.SetInputData(image_data(scene, args.scene))
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(volume_property(scene))

    renderer = vtk.vtkRenderer()
    renderer.AddVolume(volume)
    renderer.SetBackground(0, 0, 0)
    if not scene["headlight"]:
        renderer.RemoveAllLights()
        light = vtk.vtkLight()
        light.SetLightTypeToSceneLight()
        light.SetPositional(False)
        light.SetFocalPoint(0, 0, 0)
        light.SetPosition(*scene["light_direction"])
        renderer.AddLight(light)
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.AddRenderer(renderer)

    records = []
    for size in (int(s) for s in args.sizes.split(",")):
        window.SetSize(size, size)
        for cam in scene["cameras"]:
            if args.views and cam["azimuth"] not in [float(a) for a in args.views.split(",")]:
                continue
            c = renderer.GetActiveCamera()
            c.ParallelProjectionOn()
            c.SetPosition(*cam["eye"])
            c.SetFocalPoint(*cam["target"])
            c.SetViewUp(*cam["up"])
            c.SetParallelScale(0.5 * cam["ortho_height"])
            renderer.ResetCameraClippingRange()
            window.Render()  # warm-up: gradients, min-max volume, buffers
            draw, wall = [], []
            for _ in range(args.frames):
                t = time.perf_counter()
                window.Render()
                wall.append(1e3 * (time.perf_counter() - t))
                draw.append(1e3 * mapper.GetTimeToDraw())
            ms = np.median(wall if args.mapper == "gpu" else draw)
            rec = {"name": f"VTK/{args.mapper}/{size}/az{cam['azimuth']:g}",
                   "threads": args.threads, "ms": float(ms), "wall_ms": float(np.median(wall)),
                   "frames": args.frames}
            if args.mapper == "gpu":
                rec["gl_renderer"] = window.ReportCapabilities().split("OpenGL renderer string:")[-1].split("\n")[0].strip()
            records.append(rec)
            print(f"{rec['name']:<34} threads {args.threads}  {rec['ms']:8.1f} ms "
                  f"(Render() {rec['wall_ms']:.1f} ms)", flush=True)
            if args.png:
                grab = vtk.vtkWindowToImageFilter()
                grab.SetInput(window)
                grab.Update()
                writer = vtk.vtkPNGWriter()
                writer.SetFileName(f"{args.png}_{size}_az{cam['azimuth']:g}.png")
                writer.SetInputConnection(grab.GetOutputPort())
                writer.Write()
    json.dump({"threads": args.threads, "runs": records}, open(args.json, "w"), indent=1)


if __name__ == "__main__":
    main()
