/* The unit cube as 6 tetrahedra (or, with any argument, 1 hexahedron), a constant value,
   opacity 0.5 and densityScale 4 (sigma 2 over a crossing of length 1, so alpha is
   1 - exp(-2)): the mean alpha of the centre pixels at several volumeSamplingRates,
   through whichever OSPRay C API it is linked against (see docs/accuracy.md):
     cc -O2 -std=c99 bench/peers/unstructured_cube.c -Ic_api/include -LLIB -Wl,-rpath,LIB -lsciray_ospray -lm
     cc -O2 -std=c99 bench/peers/unstructured_cube.c -I../shared/peers/ospray-3.1/include -LLIB -Wl,-rpath,LIB -lospray -lm
   with LIB the folders bench/peers/side_by_side.sh makes (OUT/sciray-lib, OUT/ospray-lib). */
#include <math.h>
#include <stdio.h>
#include <stdint.h>
#include <ospray/ospray.h>
#include <ospray/ospray_util.h>
static OSPData array(const void* p, OSPDataType t, uint64_t n) {
  OSPData s = ospNewSharedData1D(p, t, n), o = ospNewData1D(t, n);
  ospCopyData1D(s, o, 0); ospRelease(s); return o;
}
int main(int argc, char** argv) {
  ospInit(&argc, (const char**)argv);
  int hex = argc > 1;
  float pos[24] = {0,0,0, 1,0,0, 1,1,0, 0,1,0, 0,0,1, 1,0,1, 1,1,1, 0,1,1};
  float val[8] = {1,1,1,1,1,1,1,1};
  uint32_t tets[24] = {0,1,2,6, 0,2,3,6, 0,3,7,6, 0,7,4,6, 0,4,5,6, 0,5,1,6};
  uint32_t hexi[8] = {0,1,2,3,4,5,6,7};
  uint32_t cells[6] = {0,4,8,12,16,20}; uint8_t types[6] = {10,10,10,10,10,10};
  uint8_t htype = 12; uint32_t hcell = 0;
  OSPVolume v = ospNewVolume("unstructured");
  ospSetObject(v, "vertex.position", array(pos, OSP_VEC3F, 8));
  ospSetObject(v, "vertex.data", array(val, OSP_FLOAT, 8));
  ospSetObject(v, "index", hex ? array(hexi, OSP_UINT, 8) : array(tets, OSP_UINT, 24));
  ospSetObject(v, "cell.index", hex ? array(&hcell, OSP_UINT, 1) : array(cells, OSP_UINT, 6));
  ospSetObject(v, "cell.type", hex ? array(&htype, OSP_UCHAR, 1) : array(types, OSP_UCHAR, 6));
  ospCommit(v);
  OSPTransferFunction tf = ospNewTransferFunction("piecewiseLinear");
  float col[3] = {1,1,1}, op[1] = {0.5f};
  ospSetObject(tf, "color", array(col, OSP_VEC3F, 1));
  ospSetObject(tf, "opacity", array(op, OSP_FLOAT, 1));
  ospSetVec2f(tf, "value", 0.f, 2.f);
  ospCommit(tf);
  OSPVolumetricModel m = ospNewVolumetricModel(v);
  ospSetObject(m, "transferFunction", tf);
  ospSetFloat(m, "densityScale", 4.f);
  ospCommit(m);
  OSPGroup g = ospNewGroup();
  ospSetObjectAsData(g, "volume", OSP_VOLUMETRIC_MODEL, m);
  ospCommit(g);
  OSPInstance inst = ospNewInstance(g); ospCommit(inst);
  OSPWorld w = ospNewWorld(); ospSetObjectAsData(w, "instance", OSP_INSTANCE, inst); ospCommit(w);
  OSPCamera cam = ospNewCamera("orthographic");
  ospSetVec3f(cam, "position", 0.5f, 0.5f, -5.f); ospSetVec3f(cam, "direction", 0, 0, 1); ospSetFloat(cam, "height", 1.f);
  ospCommit(cam);
  float rates[] = {0.25f, 1.f, 4.f, 16.f};
  for (int r = 0; r < 4; ++r) {
    OSPRenderer ren = ospNewRenderer("scivis");
    ospSetFloat(ren, "volumeSamplingRate", rates[r]);
    ospSetInt(ren, "pixelSamples", 16);
    ospCommit(ren);
    OSPFrameBuffer fb = ospNewFrameBuffer(16, 16, OSP_FB_RGBA32F, OSP_FB_COLOR);
    ospRenderFrameBlocking(fb, ren, cam, w);
    const float* px = (const float*)ospMapFrameBuffer(fb, OSP_FB_COLOR);
    double a = 0; for (int y = 4; y < 12; ++y) for (int x = 4; x < 12; ++x) a += px[4*(16*y+x)+3] / 64.0;
    printf("%s rate %5.2f: alpha %.4f (exact %.4f)\n", hex ? "hex" : "tets", rates[r], a, 1 - exp(-2.0));
    ospUnmapFrameBuffer(px, fb); ospRelease(fb); ospRelease(ren);
  }
  ospShutdown();
  return 0;
}
