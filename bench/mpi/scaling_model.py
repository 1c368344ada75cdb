#!/usr/bin/python3
"""Scaling model for distributed rendering at a given resolution (default 4K, 3840x2160):
frame time and bytes per rank for P = 2..1024 nodes (one rank per node), for
  (a) image-parallel offload with dynamic tiles (render/P, then the image to rank 0),
  (b1) data-parallel sort-last compositing by direct send (sciray: P bands, one message to
       each owner; OSPRay's DFB: 64-pixel tiles, one message per partial tile),
  (b2) data-parallel sort-last compositing with binary swap (IceT's BSWAP; radix-k generalises it).
The defaults are sciray's, measured on the 2-core development machine with
bench/mpi/bench_mpi.cpp (docs/distributed.md): c = compositing cost per pixel per fragment,
bf = 24 B per fragment pixel (RGBA, key and depth as floats), bout = 16 B per pixel to rank 0
(RGBA32F frame samples, which rank 0 accumulates); the network's B and L are parameters.

  model.py [--W 3840 --H 2160] [--B 12.5e9] [--L 1.5e-6] [--c COMP] [--Tr RENDER_S]
           [--bf 16] [--bout 4] [--tile 64] [--overlap full|cube] [--streamed] [--bounded]
  model.py --check [--bounded] [--bf 4]   # compares with published IceT / DFB / OSPRay figures

Symbols (docs/distributed.md uses the same names):
  N = W*H pixels; P nodes; B injection bandwidth per node [bytes/s]; L latency per message [s]
  c   compositing cost per pixel per fragment [s]  (the lead measures it on this machine)
  Tr  render time of the whole frame on one node [s]
  bf  bytes per fragment pixel sent for compositing; bout bytes per final pixel (RGBA8 = 4)
  nt  tiles = ceil(W/tile)*ceil(H/tile)
  f   fraction of the screen one rank's data covers: 1 ('full': every rank's region covers
      the whole image, the worst case, e.g. slabs along the view direction) or P^(-2/3)
      ('cube': the domain cut into P equal bricks, each projecting onto ~1/P^(2/3) of it)
  d   fragments per pixel = P*f (depth complexity)
"""
import argparse
import math


def overlap_fraction(P, kind):
    return 1.0 if kind == 'full' else min(1.0, P ** (-2.0 / 3.0))


def image_parallel(P, a):
    """(a) rank 0 runs the app; P workers render tiles (dynamic balancing), rank 0 gets the image."""
    N = a.W * a.H
    nt = math.ceil(a.W / a.tile) * math.ceil(a.H / a.tile)
    render = a.Tr / P
    to_rank0 = N * a.bout / a.B + N * a.acc  # rank 0's link carries the whole image; rank 0 accumulates it
    if a.streamed:                        # tiles sent as finished, overlapping rendering
        T = max(render, to_rank0) + a.L + a.tile ** 2 * a.bout / a.B
    else:                                 # OSPRay 3.1: image fetched after the frame (on map)
        T = render + to_rank0 + a.L
    return dict(T=T, bytes_worker=N * a.bout / P, bytes_rank0=N * a.bout, msgs_rank0=nt)


def direct_send(P, a):
    """(b1) each rank sends each partial tile straight to the tile's owner (nt/P tiles per owner)."""
    N = a.W * a.H
    nt = math.ceil(a.W / a.tile) * math.ceil(a.H / a.tile)
    f = overlap_fraction(P, a.overlap)
    d = P * f
    out_bytes = f * N * a.bf * (P - 1) / P
    in_bytes = (N / P) * d * a.bf * (P - 1) / P      # equal to out_bytes on average
    msgs = (P - 1) if a.bands else f * nt * (P - 1) / P
    comm = max(out_bytes, in_bytes) / a.B + a.L + msgs * a.o
    comp = a.c * (N / P) * d                          # = c*N*f: owners blend d fragments per pixel
    gather = N * a.bout / a.B + a.L + N * a.acc
    render = a.Tr / P
    T = (max(render, comm + comp) if a.streamed else render + comm + comp) + gather
    return dict(T=T, comm=comm, comp=comp, gather=gather, bytes=out_bytes, msgs=msgs, rounds=1)


def binary_swap(P, a):
    """(b2) log2 P rounds; in round k each rank sends half of the N/2^(k-1) pixels it holds.
    With --bounded (IceT's bounding boxes / run-length encoding), only the non-empty part is sent:
    after k-1 rounds a rank holds the blend of 2^(k-1) neighbouring bricks, whose footprint is
    ~ min(1, f(P) * 2^(2(k-1)/3)) of its pixels ('cube' overlap)."""
    N = a.W * a.H
    rounds = math.ceil(math.log2(P))
    f = overlap_fraction(P, a.overlap)
    out_bytes = 0.0
    fragments = 0.0
    for k in range(1, rounds + 1):
        held = N / 2 ** (k - 1)
        active = min(1.0, f * 2 ** (2 * (k - 1) / 3)) if a.bounded else 1.0
        out_bytes += held / 2 * active * a.bf
        fragments += held / 2 * active
    comm = out_bytes / a.B + rounds * a.L
    comp = a.c * fragments
    gather = N * a.bout / a.B + rounds * a.L + N * a.acc  # tree gather of the N/P pieces
    render = a.Tr / P
    T = render + comm + comp + gather                 # rounds are synchronous: no overlap
    return dict(T=T, comm=comm, comp=comp, gather=gather, bytes=out_bytes, msgs=rounds, rounds=rounds)


def table(a):
    N = a.W * a.H
    print(f"# {a.W}x{a.H} = {N/1e6:.2f} Mpx; B = {a.B/1e9:.2f} GB/s, L = {a.L*1e6:.2f} us, "
          f"c = {a.c*1e9:.2f} ns/px/fragment, Tr = {a.Tr*1e3:.1f} ms (one node), bf = {a.bf} B, "
          f"bout = {a.bout} B, tile {a.tile}, overlap {a.overlap}, {'streamed' if a.streamed else 'serial'}, "
          f"binary swap {'bounded' if a.bounded else 'full-frame'}")
    print(f"{'P':>5} | {'(a) ms':>8} {'MB->r0':>7} {'MB/wkr':>7} | {'(b1) ms':>8} {'comm':>6} {'comp':>6} "
          f"{'MB/rk':>7} {'msgs':>6} | {'(b2) ms':>8} {'comm':>6} {'comp':>6} {'MB/rk':>7} {'rnds':>4}")
    P = 2
    while P <= 1024:
        ia, ds, bs = image_parallel(P, a), direct_send(P, a), binary_swap(P, a)
        print(f"{P:>5} | {ia['T']*1e3:>8.2f} {ia['bytes_rank0']/1e6:>7.1f} {ia['bytes_worker']/1e6:>7.2f} | "
              f"{ds['T']*1e3:>8.2f} {ds['comm']*1e3:>6.2f} {ds['comp']*1e3:>6.2f} {ds['bytes']/1e6:>7.2f} {ds['msgs']:>6.0f} | "
              f"{bs['T']*1e3:>8.2f} {bs['comm']*1e3:>6.2f} {bs['comp']*1e3:>6.2f} {bs['bytes']/1e6:>7.2f} {bs['rounds']:>4}")
        P *= 2


def check(a):
    """Compositing-only predictions (Tr = 0) at the configurations of published figures, with this
    run's B, L, c, bf. 'exchange' = comm + comp (what compositing benchmarks time); 'gather' = the
    final image to one rank. For figures measured on other networks, also the bandwidth B that
    would make the model's exchange equal the published time."""
    def run(label, W, H, P, overlap, published_s, what):
        b = argparse.Namespace(**vars(a))
        b.W, b.H, b.overlap, b.Tr = W, H, overlap, 0.0
        ds, bs = direct_send(P, b), binary_swap(P, b)
        ex_ds, ex_bs = ds['comm'] + ds['comp'], bs['comm'] + bs['comp']
        line = (f"{label:<52} P={P:<6} exchange: direct-send {ex_ds*1e3:8.2f} ms, binary-swap "
                f"{ex_bs*1e3:8.2f} ms; gather {ds['gather']*1e3:6.2f} ms | published {published_s*1e3:.0f} ms ({what})")
        fixed = bs['comp'] + bs['rounds'] * b.L
        if what.startswith('compositing') and published_s > fixed:
            line += f"; binary-swap matches it at B = {bs['bytes'] / (published_s - fixed) / 1e9:.2f} GB/s"
        print(line)
    print(f"# Tr = 0; B = {a.B/1e9:.2f} GB/s, L = {a.L*1e6:.2f} us, c = {a.c*1e9:.2f} ns, bf = {a.bf} B, "
          f"binary swap {'bounded' if a.bounded else 'full-frame'}")
    run("Kendall et al. 2010: radix-k, 64 Mpx, BG/P", 8192, 8192, 32768, 'cube', 0.08,
        "compositing, bounding + RLE")
    run("Usher et al. 2019 Fig.1: Cosmic Web 2048^2, 128 KNL", 2048, 2048, 128, 'cube', 0.5,
        "whole frame, 2 FPS")
    run("Usher et al. 2019 Fig.1: DNS 4096x1024, 64 KNL", 4096, 1024, 64, 'cube', 0.2,
        "whole frame, 5 FPS")
    b = argparse.Namespace(**vars(a))
    b.W, b.H, b.Tr = 2048, 2048, 0.0
    ia = image_parallel(16, b)
    print(f"{'Usher et al. 2019 Fig.1: R-M image-par. 2048^2, 16 SKX':<52} P=16     image-parallel (a), "
          f"tiles to the display rank: {ia['T']*1e3:.2f} ms | published 125 ms (whole frame, 8 FPS)")
    run("Wald et al. 2017 Fig.9: DNS 450 GB, 8 Maverick nodes", 1920, 1080, 8, 'cube', 1 / 7.7,
        "whole frame, 7.7 fps; resolution not stated, 1080p assumed")


if __name__ == '__main__':
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--W', type=int, default=3840)
    p.add_argument('--H', type=int, default=2160)
    p.add_argument('--B', type=float, default=12.5e9, help='bytes/s per node (EDR/Omni-Path 100 Gb/s = 12.5e9)')
    p.add_argument('--L', type=float, default=1.5e-6, help='seconds per message')
    p.add_argument('--o', type=float, default=1e-6, help='CPU overhead per message sent, seconds (direct send)')
    p.add_argument('--acc', type=float, default=0.0,
                   help="rank 0's cost per pixel to accumulate the frame (sciray: measured, over rank 0's cores)")
    p.add_argument('--c', type=float, default=4e-9, help='s per pixel per fragment (sciray, measured)')
    p.add_argument('--Tr', type=float, default=0.1, help='PLACEHOLDER: one-node render time of the frame, s')
    p.add_argument('--bf', type=int, default=24, help='bytes per fragment pixel (sciray: RGBA, key, depth floats)')
    p.add_argument('--bout', type=int, default=16, help='bytes per pixel to rank 0 (sciray: RGBA32F; OSPRay: RGBA8 = 4)')
    p.add_argument('--bands', action=argparse.BooleanOptionalAction, default=True,
                   help="direct send by image bands, one message per owner (sciray); --no-bands: OSPRay's tiles")
    p.add_argument('--tile', type=int, default=64)
    p.add_argument('--overlap', choices=['full', 'cube'], default='full')
    p.add_argument('--streamed', action='store_true', help='tiles overlap rendering (DFB-style)')
    p.add_argument('--bounded', action='store_true', help='binary swap sends only non-empty pixels')
    p.add_argument('--check', action='store_true')
    a = p.parse_args()
    check(a) if a.check else table(a)
