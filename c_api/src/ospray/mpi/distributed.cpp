#include "distributed.hpp"

#include <string>
#include <vector>

#include "../device.hpp"
#include "runtime.hpp"
#include "sciray/distributed/region_renderer.hpp"
#include "sciray/mpi/data_parallel.hpp"

namespace sciray::ospray::distributed {

namespace {

/// Whether two boxes share a volume (touching faces do not count).
bool overlap(const Box3f& a, const Box3f& b) {
  return a.lower.x < b.upper.x && b.lower.x < a.upper.x && a.lower.y < b.upper.y && b.lower.y < a.upper.y &&
         a.lower.z < b.upper.z && b.lower.z < a.upper.z;
}

class MpiSession final : public Session {
public:
  explicit MpiSession(mpi_runtime::Use use)
      : use_(use), compositor_(std::make_unique<mpi::DataParallel>(MPI_COMM_WORLD)) {}
  ~MpiSession() override {
    compositor_.reset();  // its communicator goes before MPI does
    if (use_.finalize) MPI_Finalize();
  }

  void render_frame(FrameBufferObject& fb, const Renderer& renderer, const CameraObject& camera, const World& world,
                    const BuiltWorld& built, Device& device) override {
    FrameBuffer& frame = fb.frame();
    // What this rank owns: its regions, or where its data is when it names none.
    std::vector<Box3f> regions = world.regions();
    if (regions.empty() && !world.bounds().empty()) regions.push_back(world.bounds());
    check_regions(regions);
    const std::vector<std::uint32_t> tile_frames =
        compositor_->tile_frames(compositor_->owns_frames() ? &frame : nullptr, frame.tile_count());
    const shim::RendererConfig config = renderer.config(built);
    std::vector<sciray::distributed::FragmentImage> layers;
    device.arena().execute([&] {
      for (const Box3f& region : regions) {
        layers.emplace_back(frame.width(), frame.height());
        built.kernels->render_region(*built.world, config, camera.camera(), region, renderer.frame_settings(),
                                     tile_frames, layers.back());
      }
    });
    const sciray::distributed::Background background = std::visit(
        [](const auto& p) {
          return sciray::distributed::Background{p.background_color, p.background_alpha};
        },
        config);
    compositor_->composite_frame(layers, frame.width(), frame.height(), background,
                                 compositor_->owns_frames() ? &frame : nullptr, built.kernels->accumulate_tile);
  }

private:
  /// Regions of different ranks must not overlap: their fragments would have no order.
  void check_regions(const std::vector<Box3f>& mine) {
    const auto all = compositor_->all_regions(mine);
    for (std::size_t a = 0; a < all.size(); ++a)
      for (std::size_t b = a + 1; b < all.size(); ++b)
        for (const Box3f& x : all[a])
          for (const Box3f& y : all[b])
            if (overlap(x, y))
              throw Error("mpiDistributed: the regions of ranks " + std::to_string(a) + " and " + std::to_string(b) +
                          " overlap, so their images have no order to composite in (world parameter 'region')");
  }

  mpi_runtime::Use use_;
  std::unique_ptr<mpi::DataParallel> compositor_;
};

}  // namespace

std::unique_ptr<Session> start() {
  return std::make_unique<MpiSession>(mpi_runtime::initialize());
}

}  // namespace sciray::ospray::distributed
