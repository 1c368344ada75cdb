#!/usr/bin/env python3
"""A VTK pipeline's isosurface and volume, rendered by sciray from the pipeline's own arrays
and by VTK's OpenGL renderer from the same camera, side by side.

    xvfb-run -a python3 examples/python/vtk_interop.py [--out DIR] [--check]

VTK needs a display for OpenGL (xvfb-run gives it a virtual one); sciray does not. The
module depends on nothing of VTK: sciray.mesh_arrays and sciray.image_arrays read the
vtkPolyData and vtkImageData through their numpy views (pyvista objects work the same).
--check compares the silhouettes (intersection over union of the pixels unlike the
background) and fails below 0.95 for the surface and 0.85 for the volume.
"""
import argparse
import pathlib
import time

import numpy as np
import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

import sciray

WIDTH, HEIGHT = 400, 300
BACKGROUND = (0.1, 0.1, 0.12)
EYE, TARGET, FOVY = (55.0, 40.0, 80.0), (0.0, 0.0, 0.0), 30.0
SURFACE_COLOR = (0.85, 0.55, 0.3)
ISOVALUE = 170.0
# A transfer function both renderers read: blue to yellow, opacity rising over the range.
TF_COLORS = [(0.1, 0.2, 0.9), (0.2, 0.8, 0.5), (1.0, 0.9, 0.2)]
TF_RANGE = (100.0, 260.0)


def vtk_wavelet():
    """VTK's wavelet source (the 'RTData' field of ParaView's tutorials) on a 41³ grid."""
    source = vtk.vtkRTAnalyticSource()
    source.SetWholeExtent(-20, 20, -20, 20, -20, 20)
    source.Update()
    return source.GetOutput()


def vtk_isosurface(image):
    contour = vtk.vtkContourFilter()
    contour.SetInputData(image)
    contour.SetValue(0, ISOVALUE)
    contour.ComputeNormalsOn()
    contour.Update()
    return contour.GetOutput()


def vtk_render(prop):
    """VTK's OpenGL render of one prop from the shared camera, as a (height, width, 3) array."""
    renderer = vtk.vtkRenderer()
    renderer.SetBackground(*BACKGROUND)
    renderer.AddViewProp(prop)
    camera = renderer.GetActiveCamera()
    camera.SetPosition(*EYE)
    camera.SetFocalPoint(*TARGET)
    camera.SetViewUp(0, 1, 0)
    camera.SetViewAngle(FOVY)
    renderer.ResetCameraClippingRange()
    window = vtk.vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(WIDTH, HEIGHT)
    window.AddRenderer(renderer)
    window.Render()
    grab = vtk.vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    pixels = vtk_to_numpy(grab.GetOutput().GetPointData().GetScalars()).reshape(HEIGHT, WIDTH, -1)
    return pixels[::-1, :, :3]  # VTK's rows go bottom-up


def vtk_surface_prop(poly):
    mapper = vtk.vtkPolyDataMapper()
    mapper.SetInputData(poly)
    mapper.ScalarVisibilityOff()
    actor = vtk.vtkActor()
    actor.SetMapper(mapper)
    actor.GetProperty().SetColor(*SURFACE_COLOR)
    return actor


def vtk_volume_prop(image):
    colors = vtk.vtkColorTransferFunction()
    opacity = vtk.vtkPiecewiseFunction()
    for k, rgb in enumerate(TF_COLORS):
        colors.AddRGBPoint(TF_RANGE[0] + k * (TF_RANGE[1] - TF_RANGE[0]) / (len(TF_COLORS) - 1), *rgb)
    opacity.AddPoint(TF_RANGE[0], 0.0)
    opacity.AddPoint(TF_RANGE[1], 1.0)
    prop = vtk.vtkVolumeProperty()
    prop.SetColor(colors)
    prop.SetScalarOpacity(opacity)
    prop.SetInterpolationTypeToLinear()
    mapper = vtk.vtkSmartVolumeMapper()
    mapper.SetInputData(image)
    volume = vtk.vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)
    return volume


def linear(display):
    """VTK's colours are display values; sciray's are linear, encoded as sRGB on output."""
    c = np.asarray(display, dtype=np.float64)
    return tuple(np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4))


def sciray_render(scene):
    camera = sciray.Camera(position=EYE, look_at=TARGET, fovy=FOVY)
    renderer = sciray.Renderer("scivis", backgroundColor=linear(BACKGROUND))
    return np.asarray(sciray.render(scene, camera, renderer, size=(WIDTH, HEIGHT), frames=4))[..., :3]


def silhouette_iou(a, b):
    background = np.round(np.array(BACKGROUND) * 255)
    sa = np.abs(a.astype(float) - background).max(axis=-1) > 12
    sb = np.abs(b.astype(float) - background).max(axis=-1) > 12
    return (sa & sb).sum() / max((sa | sb).sum(), 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=".", help="folder for vtk_interop.png")
    parser.add_argument("--check", action="store_true", help="fail unless the silhouettes agree")
    args = parser.parse_args()

    image = vtk_wavelet()
    surface = vtk_isosurface(image)

    # sciray from the VTK objects' arrays, each handed over in a line.
    start = time.perf_counter()
    surface_scene = sciray.Scene()
    surface_scene.add_mesh(**sciray.mesh_arrays(surface), material=sciray.Material("obj", kd=linear(SURFACE_COLOR)))
    # VTK's headlight: a light from the eye, its diffuse term kd·cosθ (π times a Lambert BRDF's kd/π).
    surface_scene.add_light(sciray.Light("distant", direction=np.subtract(TARGET, EYE), intensity=np.pi))
    sciray_surface = sciray_render(surface_scene)
    volume_scene = sciray.Scene()
    tf = sciray.TransferFunction([linear(c) for c in TF_COLORS], [0.0, 1.0], value_range=TF_RANGE)
    volume_scene.add_volume(**sciray.image_arrays(image), transfer_function=tf, density=0.15)
    sciray_volume = sciray_render(volume_scene)
    sciray_seconds = time.perf_counter() - start

    start = time.perf_counter()
    vtk_surface = vtk_render(vtk_surface_prop(surface))
    vtk_volume = vtk_render(vtk_volume_prop(image))
    vtk_seconds = time.perf_counter() - start

    surface_iou = silhouette_iou(sciray_surface, vtk_surface)
    volume_iou = silhouette_iou(sciray_volume, vtk_volume)
    print(f"isosurface: {surface.GetNumberOfPolys()} triangles; silhouette IoU sciray/VTK {surface_iou:.3f}")
    print(f"volume: {image.GetDimensions()} voxels; silhouette IoU sciray/VTK {volume_iou:.3f}")
    print(f"sciray {sciray_seconds:.2f} s (scene building and 8 frames), VTK {vtk_seconds:.2f} s (two windows)")

    grid = np.concatenate([np.concatenate([sciray_surface, vtk_surface], axis=1),
                           np.concatenate([sciray_volume, vtk_volume], axis=1)], axis=0)
    out = pathlib.Path(args.out) / "vtk_interop.png"
    alpha = np.full(grid.shape[:2] + (1,), 255, np.uint8)
    sciray.Image(np.concatenate([grid.astype(np.uint8), alpha], axis=-1)).save(out)
    print(f"sciray (left) and VTK (right) -> {out}")
    if args.check and (surface_iou < 0.95 or volume_iou < 0.85):
        raise SystemExit(f"silhouettes disagree: surface {surface_iou:.3f} (needs 0.95), volume {volume_iou:.3f} "
                         "(needs 0.85)")


if __name__ == "__main__":
    main()
