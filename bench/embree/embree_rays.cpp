// Embree single-ray closest-hit throughput (rtcIntersect1) on ANCHORS.md's benchmark rays:
// 1024x1024 primary rays, then one cosine-weighted diffuse ray per primary hit.
// Build: g++ -O2 -march=native -ffp-contract=off -o /tmp/embree_rays embree_rays.cpp -lembree3 -lpthread
// Run:   /tmp/embree_rays [--view outside|inside] [--dump PREFIX] scene.obj [more.obj ...]
//
// The rays are generated in f32 with the same operations, in the same order, as kousen's Rust
// twin (crates/bvh/src/bench_rays.rs, formerly examples/support/rays.rs; glam 0.34), so they
// match it bit for bit (checked on all four ANCHORS scenes with --dump). That
// needs IEEE float arithmetic without fused multiply-adds: build with -ffp-contract=off (GCC
// fuses by default when -march=native offers FMA; the program refuses to run if it did).
#include <embree3/rtcore.h>
#include <pmmintrin.h>
#include <xmmintrin.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

static const unsigned SIDE = 1024;        // image side: SIDE^2 primary rays
static const int THREADS = 2;             // tracing threads (and Embree's build threads)
static const size_t CHUNK = 4096;         // rays per work item
static const int RUNS = 5;                // timed runs after one warm-up; the median is reported
static const float PI_F = 3.14159265358979323846f;
static const unsigned MISS = 0xffffffffu;

// ---- f32 vector arithmetic, operation for operation as glam's Vec3 ----
struct V3 { float x, y, z; };
static V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
static V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
static V3 operator-(V3 a) { return {-a.x, -a.y, -a.z}; }
static V3 operator*(float s, V3 a) { return {s * a.x, s * a.y, s * a.z}; }
static V3 operator*(V3 a, V3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
static V3 operator/(V3 a, float s) { return {a.x / s, a.y / s, a.z / s}; }
static float dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }  // (xx + yy) + zz
static V3 cross(V3 a, V3 b) { return {a.y * b.z - b.y * a.z, a.z * b.x - b.z * a.x, a.x * b.y - b.x * a.y}; }
static float length(V3 v) { return std::sqrt(dot(v, v)); }
static V3 normalize(V3 v) { return (1.0f / length(v)) * v; }  // glam: self * (1.0 / self.length())
static V3 vmin(V3 a, V3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
static V3 vmax(V3 a, V3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }

// True if the compiler fused a*b+c into one rounding (which Rust never does).
static bool fp_contracted() {
  volatile float va = 1.0f + 1.0f / 4096.0f, vc = -(1.0f + 1.0f / 2048.0f);
  float a = va, c = vc;
  return a * a + c != 0.0f;  // separately rounded: exactly 0; fused: 2^-24
}

// ---- OBJ: `v` and `f` lines only, fan triangulation (v0, vi, vi+1) in file order ----
// Unlike embree_sah.cpp, zero-area triangles are kept (as kousen's example loader does), so the
// bounding box, triangle count and primIDs are the Rust side's.
struct Mesh {
  std::vector<V3> verts;          // every `v` line
  std::vector<unsigned> index;    // 3 per triangle
  std::vector<V3> normal;         // per triangle: cross(p1 - p0, p2 - p0), unnormalized
  size_t degenerate = 0;          // triangles whose normal is not normalizable
};

static bool load_obj(const char* path, Mesh& m) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line, tok;
  std::vector<long> idx;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    if (!(ss >> tok)) continue;
    if (tok == "v") {
      V3 p{0, 0, 0};
      ss >> p.x >> p.y >> p.z;
      m.verts.push_back(p);
    } else if (tok == "f") {
      idx.clear();
      while (ss >> tok) {
        long i = std::strtol(tok.c_str(), nullptr, 10);  // stops at the first '/'
        i = i < 0 ? (long)m.verts.size() + i : i - 1;
        if (i < 0 || i >= (long)m.verts.size()) { std::fprintf(stderr, "%s: bad face index\n", path); return false; }
        idx.push_back(i);
      }
      for (size_t i = 1; i + 1 < idx.size(); i++) {
        unsigned a = idx[0], b = idx[i], c = idx[i + 1];
        m.index.insert(m.index.end(), {a, b, c});
        V3 n = cross(m.verts[b] - m.verts[a], m.verts[c] - m.verts[a]);
        if (!std::isfinite(1.0f / length(n))) m.degenerate++;
        m.normal.push_back(n);
      }
    }
  }
  return true;
}

// ---- the rays of ANCHORS.md ----
struct Ray { V3 org, dir; };
struct Hit { float t; unsigned prim; };  // prim == MISS for a miss

// Bounding box of the vertices that triangles use.
static void bounds(const Mesh& m, V3& lo, V3& hi) {
  lo = {INFINITY, INFINITY, INFINITY};
  hi = {-INFINITY, -INFINITY, -INFINITY};
  for (unsigned k : m.index) { lo = vmin(lo, m.verts[k]); hi = vmax(hi, m.verts[k]); }
}

static std::vector<Ray> primary_rays(const Mesh& m, bool inside) {
  V3 lo, hi;
  bounds(m, lo, hi);
  V3 eye, look;
  if (inside) {
    eye = lo + (hi - lo) * V3{0.85f, 0.25f, 0.5f};
    look = lo + (hi - lo) * V3{0.0f, 0.35f, 0.5f};
  } else {
    V3 center = (lo + hi) / 2.0f;
    float diagonal = length(hi - lo);
    eye = center + diagonal * V3{0.5f, 0.35f, 0.8f};
    look = center;
  }
  V3 fwd = normalize(look - eye);
  V3 right = normalize(cross(fwd, V3{0.0f, 1.0f, 0.0f}));
  V3 up = cross(right, fwd);
  float tan_half = std::tan(25.0f * (PI_F / 180.0f));  // Rust: 25f32.to_radians().tan()
  float side = (float)SIDE;
  std::vector<Ray> rays(SIDE * SIDE);
  for (unsigned i = 0; i < SIDE * SIDE; i++) {
    float x = (float)(i % SIDE), y = (float)(i / SIDE);  // y = 0 is the top row
    float u = ((x + 0.5f) / side * 2.0f - 1.0f) * tan_half;
    float v = (1.0f - (y + 0.5f) / side * 2.0f) * tan_half;
    rays[i] = {eye, normalize(fwd + u * right + v * up)};
  }
  return rays;
}

// Jarzynski & Olano's PCG hash, wrapping u32 arithmetic.
static uint32_t pcg(uint32_t x) {
  uint32_t s = x * 747796405u + 2891336453u;
  uint32_t w = ((s >> ((s >> 28) + 4)) ^ s) * 277803737u;
  return (w >> 22) ^ w;
}

// The cosine-weighted diffuse ray leaving the hit of primary ray (pixel) `i` at distance `t`
// on a triangle with unnormalized geometric normal `normal`.
static Ray diffuse_ray(uint32_t i, const Ray& primary, float t, V3 normal, float diagonal) {
  V3 n = normalize(normal);
  if (dot(n, primary.dir) > 0.0f) n = -n;  // face the ray's origin
  float u1 = (float)pcg(2 * i) * (1.0f / 4294967296.0f);  // exact power of two: same as / 2^32
  float u2 = (float)pcg(2 * i + 1) * (1.0f / 4294967296.0f);
  float phi = 2.0f * PI_F * u2;
  float r = std::sqrt(u1);
  float x = r * std::cos(phi), y = r * std::sin(phi), z = std::sqrt(1.0f - u1);
  // Duff et al. 2017's orthonormal basis around n.
  float s = std::copysign(1.0f, n.z);
  float a = -1.0f / (s + n.z);
  float b = n.x * n.y * a;
  V3 t1{1.0f + s * n.x * n.x * a, s * b, -s * n.x};
  V3 t2{b, s + n.y * n.y * a, -n.y};
  V3 p = primary.org + t * primary.dir;
  return {p + 1e-4f * diagonal * n, x * t1 + y * t2 + z * n};
}

// ---- tracing: THREADS threads take chunks of CHUNK rays, one rtcIntersect1 per ray ----
static void trace_all(RTCScene scene, const std::vector<Ray>& rays, std::vector<Hit>& hits) {
  std::atomic<size_t> next{0};
  auto work = [&] {
    // Flush denormals while tracing, as Embree asks; restored after, so ray generation stays IEEE.
    const unsigned mxcsr = _mm_getcsr();
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    for (size_t begin; (begin = next.fetch_add(CHUNK)) < rays.size();) {
      size_t end = std::min(begin + CHUNK, rays.size());
      for (size_t k = begin; k < end; k++) {
        const Ray& r = rays[k];
        RTCRayHit rh;
        rh.ray.org_x = r.org.x; rh.ray.org_y = r.org.y; rh.ray.org_z = r.org.z;
        rh.ray.dir_x = r.dir.x; rh.ray.dir_y = r.dir.y; rh.ray.dir_z = r.dir.z;
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = INFINITY;
        rh.ray.time = 0.0f;
        rh.ray.mask = 0xffffffffu;
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        hits[k] = rh.hit.geomID == RTC_INVALID_GEOMETRY_ID ? Hit{INFINITY, MISS} : Hit{rh.ray.tfar, rh.hit.primID};
      }
    }
    _mm_setcsr(mxcsr);
  };
  std::vector<std::thread> helpers;
  for (int k = 1; k < THREADS; k++) helpers.emplace_back(work);
  work();
  for (auto& h : helpers) h.join();
}

// Warm-up, then RUNS timed runs; prints one result line.
static void measure(RTCScene scene, const char* label, const char* kind, const std::vector<Ray>& rays,
                    std::vector<Hit>& hits) {
  hits.assign(rays.size(), Hit{INFINITY, MISS});
  trace_all(scene, rays, hits);
  std::vector<double> rates;
  for (int run = 0; run < RUNS; run++) {
    auto t0 = std::chrono::steady_clock::now();
    trace_all(scene, rays, hits);
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rates.push_back(rays.size() / s / 1e6);
  }
  size_t count = 0;
  double checksum = 0.0;  // sum of t over hits, in ray order
  for (const Hit& h : hits)
    if (h.prim != MISS) { count++; checksum += (double)h.t; }
  std::fprintf(stderr, "# %s %s runs (Mrays/s):", label, kind);
  for (double r : rates) std::fprintf(stderr, " %.2f", r);
  std::fprintf(stderr, "\n");
  std::sort(rates.begin(), rates.end());
  std::printf("%-27s %-7s %8zu %8zu %8.2f %18.6f\n", label, kind, rays.size(), count, rates[RUNS / 2], checksum);
  std::fflush(stdout);
}

// "dir/stem" of a path (both Sponzas are sponza.obj).
static std::string label_of(const std::string& path) {
  size_t slash = path.find_last_of('/');
  std::string file = slash == std::string::npos ? path : path.substr(slash + 1);
  std::string dir = slash == std::string::npos ? "" : path.substr(0, slash);
  size_t dslash = dir.find_last_of('/');
  std::string parent = dslash == std::string::npos ? dir : dir.substr(dslash + 1);
  std::string stem = file.substr(0, file.find_last_of('.'));
  return parent.empty() ? stem : parent + "/" + stem;
}

// --dump: raw little-endian records for cross-checking the rays against the Rust twin.
// PREFIX.primary.bin: per pixel org[3] dir[3] t prim (f32 x7, u32; t = inf, prim = ~0 on a miss);
// PREFIX.diffuse.bin: per diffuse ray pixel (u32), org[3] dir[3] t (f32), prim (u32).
static void dump(const std::string& file, const std::vector<Ray>& rays, const std::vector<Hit>& hits,
                 const std::vector<uint32_t>* pixel) {
  std::ofstream out(file, std::ios::binary);
  for (size_t k = 0; k < rays.size(); k++) {
    if (pixel) out.write((const char*)&(*pixel)[k], 4);
    out.write((const char*)&rays[k], sizeof(Ray));
    out.write((const char*)&hits[k], sizeof(Hit));
  }
  if (!out) { std::fprintf(stderr, "cannot write %s\n", file.c_str()); std::exit(1); }
}

static void bench(RTCDevice dev, const char* path, bool inside, const char* dump_prefix) {
  Mesh m;
  if (!load_obj(path, m)) { std::fprintf(stderr, "cannot read %s\n", path); std::exit(1); }
  const size_t tris = m.normal.size();
  const std::string label = label_of(path);

  // Scene: one triangle mesh, HIGH build quality, default flags (not robust).
  RTCScene scene = rtcNewScene(dev);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_NONE);
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geom, RTC_BUILD_QUALITY_HIGH);
  float* vb = (float*)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                              3 * sizeof(float), m.verts.size());
  unsigned* ib = (unsigned*)rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                    3 * sizeof(unsigned), tris);
  std::memcpy(vb, m.verts.data(), m.verts.size() * sizeof(V3));
  std::memcpy(ib, m.index.data(), m.index.size() * sizeof(unsigned));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);  // geomID 0, primID = triangle index in file order
  rtcReleaseGeometry(geom);
  auto t0 = std::chrono::steady_clock::now();
  rtcCommitScene(scene);
  double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) { std::fprintf(stderr, "Embree error on %s\n", path); std::exit(1); }
  std::fprintf(stderr, "# %s: %zu triangles (%zu zero-area), view %s, build HIGH %.1f ms (one build)\n", path, tris,
               m.degenerate, inside ? "inside" : "outside", build_ms);

  // Primary rays.
  std::vector<Ray> primary = primary_rays(m, inside);
  std::vector<Hit> primary_hits;
  measure(scene, label.c_str(), "primary", primary, primary_hits);

  // One diffuse ray per primary hit, in pixel order.
  V3 lo, hi;
  bounds(m, lo, hi);
  const float diagonal = length(hi - lo);
  std::vector<Ray> diffuse;
  std::vector<uint32_t> pixel;
  for (uint32_t i = 0; i < primary.size(); i++) {
    const Hit& h = primary_hits[i];
    if (h.prim == MISS) continue;
    diffuse.push_back(diffuse_ray(i, primary[i], h.t, m.normal[h.prim], diagonal));
    pixel.push_back(i);
  }
  std::vector<Hit> diffuse_hits;
  measure(scene, label.c_str(), "diffuse", diffuse, diffuse_hits);

  if (dump_prefix) {
    dump(std::string(dump_prefix) + ".primary.bin", primary, primary_hits, nullptr);
    dump(std::string(dump_prefix) + ".diffuse.bin", diffuse, diffuse_hits, &pixel);
  }
  rtcReleaseScene(scene);
}

int main(int argc, char** argv) {
  bool inside = false;
  const char* dump_prefix = nullptr;
  std::vector<const char*> scenes;
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    if (a == "--view" && i + 1 < argc) {
      std::string v = argv[++i];
      if (v != "inside" && v != "outside") { std::fprintf(stderr, "--view: inside or outside\n"); return 2; }
      inside = v == "inside";
    } else if (a == "--dump" && i + 1 < argc) {
      dump_prefix = argv[++i];
    } else {
      scenes.push_back(argv[i]);
    }
  }
  if (scenes.empty()) {
    std::fprintf(stderr, "usage: %s [--view outside|inside] [--dump PREFIX] scene.obj [...]\n", argv[0]);
    return 2;
  }
  if (dump_prefix && scenes.size() > 1) { std::fprintf(stderr, "--dump takes one scene\n"); return 2; }
  if (fp_contracted()) {
    std::fprintf(stderr, "built with floating-point contraction: rebuild with -ffp-contract=off\n");
    return 1;
  }
  RTCDevice dev = rtcNewDevice("threads=2");
  if (!dev) { std::fprintf(stderr, "rtcNewDevice failed\n"); return 1; }
  std::printf("# Embree %s, device threads=2, %d tracing threads, rtcIntersect1, %ux%u, median of %d\n",
              RTC_VERSION_STRING, THREADS, SIDE, SIDE, RUNS);
  std::printf("%-27s %-7s %8s %8s %8s %18s\n", "scene", "rays", "count", "hits", "Mrays/s", "checksum(sum t)");
  for (const char* s : scenes) bench(dev, s, inside, dump_prefix);
  rtcReleaseDevice(dev);
  return 0;
}
