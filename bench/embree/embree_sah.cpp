// Embree BVH-builder benchmark: build time and SAH cost of binary BVHs over an OBJ's triangles.
// Build: g++ -O2 -o /tmp/embree_sah embree_sah.cpp -lembree3
// Run:   /tmp/embree_sah scene.obj [more.obj ...]
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

struct V3 { float x, y, z; };
static V3 sub(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
static float comp(const V3& v, unsigned d) { return d == 0 ? v.x : d == 1 ? v.y : v.z; }

struct Box { float lo[3], hi[3]; };
static Box empty_box() { return {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}}; }
static void grow(Box& b, const float* lo, const float* hi) {
  for (int k = 0; k < 3; k++) { b.lo[k] = std::min(b.lo[k], lo[k]); b.hi[k] = std::max(b.hi[k], hi[k]); }
}
static void grow_point(Box& b, V3 p) { float q[3] = {p.x, p.y, p.z}; grow(b, q, q); }
static double area(const Box& b) {
  double dx = (double)b.hi[0] - b.lo[0], dy = (double)b.hi[1] - b.lo[1], dz = (double)b.hi[2] - b.lo[2];
  if (dx < 0 || dy < 0 || dz < 0) return 0.0;
  return 2.0 * (dx * dy + dy * dz + dz * dx);
}
static Box from_rtc(const RTCBounds& r) { return {{r.lower_x, r.lower_y, r.lower_z}, {r.upper_x, r.upper_y, r.upper_z}}; }

// ---- OBJ: `v` and `f` lines only, fan triangulation, negative indices, zero-area dropped ----
struct Mesh { std::vector<V3> tri; size_t dropped = 0; };  // tri: 3 vertices per triangle

static bool load_obj(const char* path, Mesh& m) {
  std::ifstream in(path);
  if (!in) return false;
  std::vector<V3> verts;
  std::string line, tok;
  std::vector<long> idx;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    if (!(ss >> tok)) continue;
    if (tok == "v") {
      V3 p{0, 0, 0};
      ss >> p.x >> p.y >> p.z;
      verts.push_back(p);
    } else if (tok == "f") {
      idx.clear();
      while (ss >> tok) {
        long i = std::strtol(tok.c_str(), nullptr, 10);  // stops at the first '/'
        idx.push_back(i < 0 ? (long)verts.size() + i : i - 1);
      }
      for (size_t i = 1; i + 1 < idx.size(); i++) {
        long a = idx[0], b = idx[i], c = idx[i + 1];
        if (a < 0 || b < 0 || c < 0 || a >= (long)verts.size() || b >= (long)verts.size() || c >= (long)verts.size()) {
          std::fprintf(stderr, "%s: bad face index\n", path);
          return false;
        }
        V3 e1 = sub(verts[b], verts[a]), e2 = sub(verts[c], verts[a]);
        V3 n{e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x};
        float rcp = 1.0f / std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
        if (!(std::isfinite(rcp) && rcp > 0.0f)) { m.dropped++; continue; }
        m.tri.push_back(verts[a]); m.tri.push_back(verts[b]); m.tri.push_back(verts[c]);
      }
    }
  }
  return true;
}

// ---- tree built through the callbacks ----
struct Node { int is_leaf; };
struct Inner { Node base; Box box[2]; Node* child[2]; };
struct Leaf { Node base; unsigned count; Box box; };

static void* create_node(RTCThreadLocalAllocator alloc, unsigned int child_count, void*) {
  if (child_count != 2) { std::fprintf(stderr, "unexpected child count %u\n", child_count); std::abort(); }
  Inner* n = (Inner*)rtcThreadLocalAlloc(alloc, sizeof(Inner), 16);
  n->base.is_leaf = 0;
  return n;
}
static void set_children(void* node, void** children, unsigned int count, void*) {
  for (unsigned i = 0; i < count; i++) ((Inner*)node)->child[i] = (Node*)children[i];
}
static void set_bounds(void* node, const RTCBounds** bounds, unsigned int count, void*) {
  for (unsigned i = 0; i < count; i++) ((Inner*)node)->box[i] = from_rtc(*bounds[i]);
}
static void* create_leaf(RTCThreadLocalAllocator alloc, const RTCBuildPrimitive* prims, size_t n, void*) {
  Leaf* l = (Leaf*)rtcThreadLocalAlloc(alloc, sizeof(Leaf), 16);
  l->base.is_leaf = 1;
  l->count = (unsigned)n;
  l->box = empty_box();
  for (size_t i = 0; i < n; i++) grow(l->box, &prims[i].lower_x, &prims[i].upper_x);
  return l;
}

// Splits a (possibly already clipped) triangle reference at plane `dim = pos`: the triangle is
// clipped against the plane, and both halves are intersected with the reference's current box.
static void split_prim(const RTCBuildPrimitive* p, unsigned dim, float pos, RTCBounds* left, RTCBounds* right, void* user) {
  const V3* t = &((const Mesh*)user)->tri[3 * (size_t)p->primID];
  Box l = empty_box(), r = empty_box();
  for (int i = 0; i < 3; i++) {
    V3 a = t[i], b = t[(i + 1) % 3];
    float da = comp(a, dim), db = comp(b, dim);
    if (da <= pos) grow_point(l, a);
    if (da >= pos) grow_point(r, a);
    if ((da < pos && db > pos) || (da > pos && db < pos)) {
      float s = (pos - da) / (db - da);
      V3 q{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z)};
      grow_point(l, q); grow_point(r, q);
    }
  }
  const float plo[3] = {p->lower_x, p->lower_y, p->lower_z}, phi[3] = {p->upper_x, p->upper_y, p->upper_z};
  for (int k = 0; k < 3; k++) {
    l.lo[k] = std::max(l.lo[k], plo[k]); l.hi[k] = std::min(l.hi[k], phi[k]);
    r.lo[k] = std::max(r.lo[k], plo[k]); r.hi[k] = std::min(r.hi[k], phi[k]);
  }
  l.hi[dim] = std::min(l.hi[dim], pos);
  r.lo[dim] = std::max(r.lo[dim], pos);
  *left = {l.lo[0], l.lo[1], l.lo[2], 0, l.hi[0], l.hi[1], l.hi[2], 0};
  *right = {r.lo[0], r.lo[1], r.lo[2], 0, r.hi[0], r.hi[1], r.hi[2], 0};
}

// ---- statistics: SAH relative to the root, nodes, leaves, depth (lone leaf = 1), references ----
struct Stats { double weighted = 0; size_t nodes = 0, leaves = 0, refs = 0, depth = 0; };

static void walk(const Node* n, const Box& box, size_t level, Stats& s) {
  s.nodes++;
  s.depth = std::max(s.depth, level);
  if (n->is_leaf) {
    const Leaf* l = (const Leaf*)n;
    s.leaves++;
    s.refs += l->count;
    s.weighted += area(l->box) * l->count;  // C_isect = 1
    return;
  }
  const Inner* in = (const Inner*)n;
  s.weighted += area(box);  // C_trav = 1
  for (int i = 0; i < 2; i++) walk(in->child[i], in->box[i], level + 1, s);
}

static Box root_box(const Node* root) {
  if (root->is_leaf) return ((const Leaf*)root)->box;
  const Inner* in = (const Inner*)root;
  Box b = in->box[0];
  grow(b, in->box[1].lo, in->box[1].hi);
  return b;
}

static void bench(RTCDevice dev, const char* path, Mesh& m, RTCBuildQuality q, unsigned max_leaf, bool splits) {
  const size_t n = m.tri.size() / 3;
  const size_t capacity = splits ? 2 * n : n;  // room for split references (Embree's default 2x)
  std::vector<RTCBuildPrimitive> pristine(n), prims(capacity);
  for (size_t i = 0; i < n; i++) {
    Box b = empty_box();
    for (int k = 0; k < 3; k++) grow_point(b, m.tri[3 * i + k]);
    pristine[i] = {b.lo[0], b.lo[1], b.lo[2], 0, b.hi[0], b.hi[1], b.hi[2], (unsigned)i};
  }
  RTCBVH bvh = rtcNewBVH(dev);
  std::vector<double> ms;
  Node* root = nullptr;
  for (int run = 0; run < 6; run++) {  // run 0 is the warm-up
    std::copy(pristine.begin(), pristine.end(), prims.begin());  // the builder reorders/overwrites
    RTCBuildArguments a = rtcDefaultBuildArguments();
    a.buildQuality = q;
    a.buildFlags = RTC_BUILD_FLAG_NONE;
    a.maxBranchingFactor = 2;
    a.maxDepth = 64;  // kousen's MAX_DEPTH (Embree's default is 32)
    a.minLeafSize = 1;
    a.maxLeafSize = max_leaf;
    a.traversalCost = 1.0f;
    a.intersectionCost = 1.0f;
    a.bvh = bvh;
    a.primitives = prims.data();
    a.primitiveCount = n;
    a.primitiveArrayCapacity = capacity;
    a.createNode = create_node;
    a.setNodeChildren = set_children;
    a.setNodeBounds = set_bounds;
    a.createLeaf = create_leaf;
    a.splitPrimitive = splits ? split_prim : nullptr;
    a.userPtr = &m;
    auto t0 = std::chrono::steady_clock::now();
    root = (Node*)rtcBuildBVH(&a);
    auto t1 = std::chrono::steady_clock::now();
    if (!root) { std::fprintf(stderr, "build failed: error %d\n", (int)rtcGetDeviceError(dev)); std::exit(1); }
    if (run > 0) ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
  }
  std::sort(ms.begin(), ms.end());
  Stats s;
  Box rb = root_box(root);
  walk(root, rb, 1, s);
  const char* qn = q == RTC_BUILD_QUALITY_HIGH ? "HIGH" : q == RTC_BUILD_QUALITY_MEDIUM ? "MEDIUM" : "LOW";
  std::printf("%-45s %8zu %-6s %3u %-3s %9.1f %9.4f %8zu %8zu %4zu %8zu\n", path, n, qn, max_leaf,
              splits ? "yes" : "no", ms[ms.size() / 2], s.weighted / area(rb), s.nodes, s.leaves, s.depth, s.refs);
  std::fflush(stdout);
  rtcReleaseBVH(bvh);
}

int main(int argc, char** argv) {
  if (argc < 2) { std::fprintf(stderr, "usage: %s scene.obj [...]\n", argv[0]); return 2; }
  RTCDevice dev = rtcNewDevice("threads=2");
  if (!dev) { std::fprintf(stderr, "rtcNewDevice failed\n"); return 1; }
  std::printf("# Embree %s (RTC_VERSION %d), device threads=2\n", RTC_VERSION_STRING, RTC_VERSION);
  std::printf("%-45s %8s %-6s %3s %-3s %9s %9s %8s %8s %4s %8s\n", "scene", "tris", "qual", "ml", "spl",
              "build_ms", "SAH", "nodes", "leaves", "dep", "refs");
  for (int i = 1; i < argc; i++) {
    Mesh m;
    if (!load_obj(argv[i], m)) { std::fprintf(stderr, "cannot read %s\n", argv[i]); return 1; }
    std::fprintf(stderr, "# %s: %zu triangles, %zu zero-area dropped\n", argv[i], m.tri.size() / 3, m.dropped);
    for (unsigned ml : {1u, 2u}) {
      bench(dev, argv[i], m, RTC_BUILD_QUALITY_MEDIUM, ml, false);
      bench(dev, argv[i], m, RTC_BUILD_QUALITY_HIGH, ml, false);
      bench(dev, argv[i], m, RTC_BUILD_QUALITY_HIGH, ml, true);
    }
  }
  rtcReleaseDevice(dev);
  return 0;
}
