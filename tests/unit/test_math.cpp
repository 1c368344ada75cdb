// Math and lane helpers: the packet instantiations must compute what the scalar ones do.
#include <catch2/catch.hpp>

#include "sciray/math/box.hpp"
#include "sciray/math/color.hpp"
#include "sciray/math/sequence.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/simd/arch.hpp"

using namespace sciray;

TEST_CASE("Vec3 scalar operations", "[math]") {
  const Vec3f a{1.f, 2.f, 3.f}, b{-2.f, 0.5f, 4.f};
  CHECK(dot(a, b) == Approx(-2.f + 1.f + 12.f));
  const Vec3f c = cross(a, b);
  CHECK(dot(c, a) == Approx(0.f).margin(1e-5));
  CHECK(dot(c, b) == Approx(0.f).margin(1e-5));
  CHECK(c == Vec3f{2.f * 4.f - 3.f * 0.5f, 3.f * -2.f - 1.f * 4.f, 1.f * 0.5f - 2.f * -2.f});
  CHECK(length(normalize(b)) == Approx(1.f));
  CHECK(min(a, b) == Vec3f{-2.f, 0.5f, 3.f});
  CHECK(max(a, b) == Vec3f{1.f, 2.f, 4.f});
}

TEST_CASE("perpendicular gives an orthonormal direction for any unit vector", "[math]") {
  for (const Vec3f n : {Vec3f{0, 0, 1}, Vec3f{0, 0, -1}, normalize(Vec3f{1, 2, 3}), normalize(Vec3f{-1e-4f, 1, 0})}) {
    const Vec3f t = perpendicular(n);
    CHECK(length(t) == Approx(1.f).epsilon(1e-5));
    CHECK(dot(t, n) == Approx(0.f).margin(1e-5));
  }
}

TEMPLATE_TEST_CASE("Vec3 packet lanes equal the scalar result", "[math][simd]", xsimd::sse2) {
  using F = simd::Float<TestType>;
  constexpr int W = simd::width<TestType>;
  float xs[W], ys[W], zs[W];
  for (int i = 0; i < W; ++i) xs[i] = 0.5f + i, ys[i] = -1.f + 0.25f * i, zs[i] = 3.f - i;
  const Vec3<F> p{F::load_unaligned(xs), F::load_unaligned(ys), F::load_unaligned(zs)};
  const Vec3f q{0.3f, -0.7f, 2.f};
  const auto n = normalize(cross(p, Vec3<F>(q)));
  const F d = dot(p, Vec3<F>(q));
  for (int i = 0; i < W; ++i) {
    const Vec3f pi{xs[i], ys[i], zs[i]};
    const Vec3f ni = normalize(cross(pi, q));
    CHECK(simd::lane(n.x, i) == Approx(ni.x));
    CHECK(simd::lane(n.y, i) == Approx(ni.y));
    CHECK(simd::lane(n.z, i) == Approx(ni.z));
    CHECK(simd::lane(d, i) == Approx(dot(pi, q)));
  }
}

TEST_CASE("int select and gather follow the float mask", "[math][simd]") {
  using A = xsimd::sse2;
  using F = simd::Float<A>;
  using I = simd::Int<A>;
  const float base[] = {10.f, 11.f, 12.f, 13.f, 14.f};
  const F x{0.f, 1.f, 2.f, 3.f};
  const auto mask = x > F(1.5f);
  const I picked = simd::select(mask, I(4), I(1));
  const F gathered = simd::gather<A>(base, picked);
  CHECK(simd::lane(gathered, 0) == 11.f);
  CHECK(simd::lane(gathered, 1) == 11.f);
  CHECK(simd::lane(gathered, 2) == 14.f);
  CHECK(simd::lane(gathered, 3) == 14.f);
  const I valid = simd::valid_lanes(mask);
  CHECK(simd::lane(valid, 0) == 0);
  CHECK(simd::lane(valid, 3) == -1);
}

TEST_CASE("Box3f bounds", "[math]") {
  Box3f box;
  CHECK(box.empty());
  box.extend(Vec3f{1, 2, 3});
  box.extend(Vec3f{-1, 5, 0});
  CHECK_FALSE(box.empty());
  CHECK(box.center() == Vec3f{0.f, 3.5f, 1.5f});
  CHECK(box.size() == Vec3f{2.f, 3.f, 3.f});
}

TEST_CASE("sRGB transfer function", "[math][color]") {
  CHECK(linear_to_srgb(0.f) == 0.f);
  CHECK(linear_to_srgb(1.f) == Approx(1.f));
  CHECK(linear_to_srgb(0.0031308f) == Approx(0.04045f).epsilon(1e-3));
  CHECK(linear_to_srgb(0.214041f) == Approx(0.5f).epsilon(1e-4));
  for (float v = 0.f; v <= 1.f; v += 0.01f) CHECK(srgb_to_linear(linear_to_srgb(v)) == Approx(v).margin(1e-5));
  CHECK(to_unorm8(0.5f) == 128);
  CHECK(to_unorm8(2.f) == 255);
  CHECK(to_unorm8(-1.f) == 0);
}

TEST_CASE("ISA requests resolve to what the CPU runs", "[simd][isa]") {
  const auto sse_only = [](simd::Isa isa) { return isa == simd::Isa::sse42 || isa == simd::Isa::scalar; };
  CHECK(simd::resolve_isa("auto", sse_only) == simd::Isa::sse42);
  CHECK(simd::resolve_isa("scalar", sse_only) == simd::Isa::scalar);
  CHECK(simd::resolve_isa("sse42", sse_only) == simd::Isa::sse42);
  CHECK_THROWS_WITH(simd::resolve_isa("avx512", sse_only),
                    "ISA 'avx512' is not supported by this CPU (best available: sse4.2)");
  CHECK_THROWS_WITH(simd::resolve_isa("neon", sse_only), Catch::Contains("unknown ISA 'neon'"));
  CHECK(simd::resolve_isa("auto") == simd::best_supported_isa());
  for (auto isa : simd::all_isas) CHECK(simd::parse_isa(simd::isa_name(isa)) == isa);
}
