#include "bolo/sim/scene/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <string>
#include <thread>

namespace bolo::sim::scene {
namespace {

constexpr double kTMin = 1e-6;
// Long objects (a sidewalk along a whole street) would make every BVH node along the street
// large: the BVH holds them as segments of kSegment metres (shaded as the whole object).
constexpr double kHuge = 48.0;
constexpr double kSegment = 24.0;

// Box in its own frame with the world-to-box transform: p_box = r * p_world + t.
struct XBox {
  Eigen::Matrix3d r;
  Eigen::Vector3d t;
  Eigen::Vector3d lo, hi;    // the part tested (a long box is split into segments)
  Eigen::Vector3d slo, shi;  // the whole box, for the surface coordinates
  std::size_t index;  // into scene.boxes
  bool aligned;       // r is the identity: test wlo/whi in the world frame
  Eigen::Vector3d wlo, whi;  // aligned: the box in world coordinates
};

struct Aabb {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(kInfinity);
  Eigen::Vector3d hi = Eigen::Vector3d::Constant(-kInfinity);
  void add(const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  void add(const Aabb& b) {
    lo = lo.cwiseMin(b.lo);
    hi = hi.cwiseMax(b.hi);
  }
  Eigen::Vector3d centre() const { return 0.5 * (lo + hi); }
};

Aabb box_bounds(const Eigen::Isometry3d& world_from_box, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  Aabb a;
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d p((c & 1) ? hi.x() : lo.x(), (c & 2) ? hi.y() : lo.y(), (c & 4) ? hi.z() : lo.z());
    a.add(world_from_box * p);
  }
  return a;
}

XBox make_xbox(const Eigen::Isometry3d& world_from_box, const Box& b, std::size_t index) {
  XBox x;
  x.r = world_from_box.linear().transpose();
  x.t = -(x.r * world_from_box.translation());
  x.lo = x.slo = b.lo;
  x.hi = x.shi = b.hi;
  x.index = index;
  x.aligned = x.r == Eigen::Matrix3d::Identity();
  x.wlo = x.lo - x.t;
  x.whi = x.hi - x.t;
  return x;
}

inline bool hit_aabb(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Eigen::Vector3d& o,
                     const Eigen::Vector3d& inv, double tmax) {
  double t0 = 0.0, t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    double ta = (lo[a] - o[a]) * inv[a], tb = (hi[a] - o[a]) * inv[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  return t0 <= t1;
}

// A world ray with its inverse direction (huge but finite for zero components).
struct RayD {
  Eigen::Vector3d o, d, inv;
  RayD(const Eigen::Vector3d& org, const Eigen::Vector3d& dir) : o(org), d(dir) {
    for (int k = 0; k < 3; ++k) {
      const double dk = std::abs(d[k]) < 1e-30 ? (std::signbit(d[k]) ? -1e-30 : 1e-30) : d[k];
      inv[k] = std::clamp(1.0 / dk, -1e30, 1e30);
    }
  }
};

// Axis-aligned box in world coordinates (branch-free slabs); the face is found only for a hit.
inline bool hit_aligned(const XBox& b, const RayD& r, double& tbest, int& face) {
  double tn = -kInfinity, tf = kInfinity;
  double te[3];
  for (int a = 0; a < 3; ++a) {
    const double t0 = (b.wlo[a] - r.o[a]) * r.inv[a], t1 = (b.whi[a] - r.o[a]) * r.inv[a];
    te[a] = std::min(t0, t1);
    tn = std::max(tn, te[a]);
    tf = std::min(tf, std::max(t0, t1));
  }
  if (tn > tf) return false;
  int axis = 0;
  double th;
  if (tn > kTMin) {
    th = tn;
    axis = te[0] == tn ? 0 : (te[1] == tn ? 1 : 2);
    if (th >= tbest) return false;
    face = 2 * axis + (r.d[axis] > 0.0 ? 1 : 0);  // entering through the lo face when moving +
  } else if (tf > kTMin) {
    th = tf;
    if (th >= tbest) return false;
    for (int a = 0; a < 3; ++a) {
      const double tx = std::max((b.wlo[a] - r.o[a]) * r.inv[a], (b.whi[a] - r.o[a]) * r.inv[a]);
      if (tx == tf) axis = a;
    }
    face = 2 * axis + (r.d[axis] > 0.0 ? 0 : 1);  // leaving through the hi face when moving +
  } else {
    return false;
  }
  tbest = th;
  return true;
}

// Slab test in the box frame. Faces: 0:+x 1:-x 2:+y 3:-y 4:+z 5:-z. A ray starting inside hits
// the face it leaves through.
inline bool hit_box(const XBox& b, const Eigen::Vector3d& o, const Eigen::Vector3d& d, double& tbest, int& face) {
  const Eigen::Vector3d ol = b.r * o + b.t;
  const Eigen::Vector3d dl = b.r * d;
  double tnear = -kInfinity, tfar = kInfinity;
  int fnear = -1, ffar = -1;
  for (int a = 0; a < 3; ++a) {
    if (dl[a] == 0.0) {
      if (ol[a] < b.lo[a] || ol[a] > b.hi[a]) return false;
      continue;
    }
    const double inv = 1.0 / dl[a];
    const double tl = (b.lo[a] - ol[a]) * inv, th = (b.hi[a] - ol[a]) * inv;
    double te, tx;
    int fe, fx;
    if (inv > 0.0) {
      te = tl, fe = 2 * a + 1, tx = th, fx = 2 * a;
    } else {
      te = th, fe = 2 * a, tx = tl, fx = 2 * a + 1;
    }
    if (te > tnear) tnear = te, fnear = fe;
    if (tx < tfar) tfar = tx, ffar = fx;
    if (tnear > tfar) return false;
  }
  double th;
  int f;
  if (tnear > kTMin) {
    th = tnear, f = fnear;
  } else if (tfar > kTMin) {
    th = tfar, f = ffar;
  } else {
    return false;
  }
  if (th >= tbest || f < 0) return false;
  tbest = th;
  face = f;
  return true;
}

// A bounded quad, or a segment of one (bounds within the quad's).
struct XQuad {
  std::size_t index;  // into scene.quads
  double u_min, u_max, v_min, v_max;
};

inline bool hit_quad(const Quad& q, const XQuad& xq, const Eigen::Vector3d& n, const Eigen::Vector3d& o,
                     const Eigen::Vector3d& d, double& tbest, double& u, double& v) {
  const double den = n.dot(d);
  if (den == 0.0) return false;
  const double th = n.dot(q.origin - o) / den;
  if (!(th > kTMin) || th >= tbest) return false;
  const Eigen::Vector3d p = o + th * d - q.origin;
  const double pu = p.dot(q.u_axis), pv = p.dot(q.v_axis);
  if (pu < xq.u_min || pu > xq.u_max || pv < xq.v_min || pv > xq.v_max) return false;
  tbest = th;
  u = pu;
  v = pv;
  return true;
}

// 32-byte BVH node with single-precision bounds rounded outwards (the node test is only a
// filter; hits are computed in double). Inner nodes: the left child is the next node.
struct Node {
  float lo[3];
  std::int32_t a;  // inner: index of the right child; leaf: first item
  float hi[3];
  std::int32_t b;  // inner: -1 - split axis; leaf: item count (> 0)
};
static_assert(sizeof(Node) == 32);

float round_down(double x) {
  const double m = x - 1e-4 - 1e-6 * std::abs(x);
  float f = static_cast<float>(m);
  if (static_cast<double>(f) > m) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}
float round_up(double x) {
  const double m = x + 1e-4 + 1e-6 * std::abs(x);
  float f = static_cast<float>(m);
  if (static_cast<double>(f) < m) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}

// Per-ray constants of the node test. Zero direction components get a huge finite inverse so
// that 0 * inv never makes a NaN.
struct RayF {
  float o[3], inv[3];
  explicit RayF(const Eigen::Vector3d& org, const Eigen::Vector3d& d) {
    for (int k = 0; k < 3; ++k) {
      o[k] = static_cast<float>(org[k]);
      const double dk = std::abs(d[k]) < 1e-30 ? (std::signbit(d[k]) ? -1e-30 : 1e-30) : d[k];
      inv[k] = static_cast<float>(std::clamp(1.0 / dk, -1e30, 1e30));
    }
  }
};

inline bool hit_node(const Node& n, const RayF& r, float tmax) {
  const float x0 = (n.lo[0] - r.o[0]) * r.inv[0], x1 = (n.hi[0] - r.o[0]) * r.inv[0];
  const float y0 = (n.lo[1] - r.o[1]) * r.inv[1], y1 = (n.hi[1] - r.o[1]) * r.inv[1];
  const float z0 = (n.lo[2] - r.o[2]) * r.inv[2], z1 = (n.hi[2] - r.o[2]) * r.inv[2];
  const float tn = std::max(std::max(std::min(x0, x1), std::min(y0, y1)), std::max(std::min(z0, z1), 0.0f));
  const float tf = std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::min(std::max(z0, z1), tmax));
  return tn <= tf;
}

struct Item {
  bool box;
  std::uint32_t index;  // into Impl::sboxes or Impl::xquads
};

struct Best {
  double t = kInfinity;
  RayHit::Kind kind = RayHit::Kind::sky;
  std::size_t index = 0;  // quads: scene index; static box: sboxes index; moving: frame index
  bool moving = false;
  int face = -1;
  double u = 0.0, v = 0.0;
};

// An image tile's frustum: inward normals (camera frame) of 4 planes through the eye that
// contain every ray of the tile; valid = false when no such planes were found.
struct TilePlanes {
  Eigen::Vector3d n[4];
  bool valid = false;
};

struct Candidate {
  double dist;  // lower bound of the hit distance
  int item;     // into items
};

constexpr std::size_t kTile = 8;             // tile edge, pixels
constexpr std::size_t kMaxCandidates = 48;  // beyond this a tile traverses the BVH per ray

struct Group {
  Aabb bounds;
  std::size_t first = 0, count = 0;
  // Bounding cone seen from the frame's eye: rays with dot(d, axis) < cos_max miss the group.
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  double cos_max = -2.0;
};

struct Frame {
  double t = 0.0;
  std::vector<double> base;     // per material
  std::vector<XBox> moving;     // moving boxes at time t
  std::vector<Group> groups;    // one per motion, visible ones only when culling
  // Rays all start at `eye`: every BVH node containing it would pass the node test, so the
  // traversal starts from the nodes just below them (`roots`, farthest first).
  Eigen::Vector3d eye = Eigen::Vector3d::Zero();
  std::vector<int> roots;
};

}  // namespace

struct Renderer::Impl {
  Scene scene;
  Camera camera;
  RenderOptions options;
  unsigned threads = 1;
  std::vector<Eigen::Vector3d> rays;  // camera frame, (H*ss) x (W*ss), unit
  double cone_cos = -1.0;             // cos of the widest ray's angle to the optical axis
  std::vector<Eigen::Vector3d> quad_normals;
  std::vector<std::size_t> unbounded_quads;
  std::vector<XQuad> xquads;
  std::vector<Aabb> item_bounds;   // per item
  std::vector<TilePlanes> tiles;   // per kTile x kTile tile, row-major
  std::size_t tiles_x = 0;
  std::vector<XBox> sboxes;
  std::vector<Node> nodes;
  std::vector<Item> items;
  std::vector<std::vector<std::size_t>> motion_boxes;  // box indices per motion

  void build();
  int build_node(std::vector<Item>& its, std::vector<Aabb>& bounds, int first, int count);
  Frame make_frame(double t, const Pose* cull_pose) const;
  void set_eye(Frame& f, const Eigen::Vector3d& eye) const;
  void intersect(const Frame& f, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Best& best) const;
  void intersect_unbounded(const Eigen::Vector3d& o, const Eigen::Vector3d& d, Best& best) const;
  void test_item(const Item& it, const RayD& r, Best& best) const;
  void intersect_bvh(const Frame& f, const RayD& r, Best& best) const;
  void intersect_moving(const Frame& f, const RayD& r, Best& best) const;
  // Fills the tile's static candidates (all of them, unsorted, when there are more than
  // kMaxCandidates) and the moving groups its frustum meets.
  void tile_candidates(const Frame& f, const Eigen::Matrix3d& r, const TilePlanes& tp, double dmax,
                       std::vector<Candidate>& out, std::vector<std::size_t>& groups) const;
  void intersect_group(const Frame& f, const Group& g, const RayD& r, Best& best) const;
  double shade(const Frame& f, const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Best& best,
               RayHit* out) const;
};

void Renderer::Impl::build() {
  const std::size_t nq = scene.quads.size();
  quad_normals.resize(nq);
  std::vector<Item> its;
  std::vector<Aabb> bounds;
  for (std::size_t i = 0; i < nq; ++i) {
    const Quad& q = scene.quads[i];
    quad_normals[i] = q.u_axis.cross(q.v_axis);
    if (!std::isfinite(q.u_min) || !std::isfinite(q.u_max) || !std::isfinite(q.v_min) || !std::isfinite(q.v_max)) {
      unbounded_quads.push_back(i);
      continue;
    }
    const int nu = q.u_max - q.u_min > kHuge ? static_cast<int>(std::ceil((q.u_max - q.u_min) / kSegment)) : 1;
    const int nv = q.v_max - q.v_min > kHuge ? static_cast<int>(std::ceil((q.v_max - q.v_min) / kSegment)) : 1;
    for (int iu = 0; iu < nu; ++iu) {
      for (int iv = 0; iv < nv; ++iv) {
        XQuad xq{i, q.u_min + (q.u_max - q.u_min) * iu / nu, q.u_min + (q.u_max - q.u_min) * (iu + 1) / nu,
                 q.v_min + (q.v_max - q.v_min) * iv / nv, q.v_min + (q.v_max - q.v_min) * (iv + 1) / nv};
        if (iu == nu - 1) xq.u_max = q.u_max;
        if (iv == nv - 1) xq.v_max = q.v_max;
        Aabb a;
        for (double u : {xq.u_min, xq.u_max})
          for (double v : {xq.v_min, xq.v_max}) a.add(q.origin + u * q.u_axis + v * q.v_axis);
        its.push_back({false, static_cast<std::uint32_t>(xquads.size())});
        bounds.push_back(a);
        xquads.push_back(xq);
      }
    }
  }
  motion_boxes.assign(scene.motions.size(), {});
  for (std::size_t i = 0; i < scene.boxes.size(); ++i) {
    const Box& b = scene.boxes[i];
    if (b.motion >= 0) {
      motion_boxes[static_cast<std::size_t>(b.motion)].push_back(i);
      continue;
    }
    const XBox whole = make_xbox(b.placement, b, i);
    const Eigen::Vector3d ext = b.hi - b.lo;
    int axis = 0;
    if (ext.y() > ext[axis]) axis = 1;
    if (ext.z() > ext[axis]) axis = 2;
    const int n = ext[axis] > kHuge ? static_cast<int>(std::ceil(ext[axis] / kSegment)) : 1;
    for (int k = 0; k < n; ++k) {
      XBox seg = whole;
      seg.lo[axis] = b.lo[axis] + ext[axis] * k / n;
      seg.hi[axis] = k == n - 1 ? b.hi[axis] : b.lo[axis] + ext[axis] * (k + 1) / n;
      seg.wlo = seg.lo - seg.t;
      seg.whi = seg.hi - seg.t;
      its.push_back({true, static_cast<std::uint32_t>(sboxes.size())});
      bounds.push_back(box_bounds(b.placement, seg.lo, seg.hi));
      sboxes.push_back(seg);
    }
  }
  nodes.clear();
  items.clear();
  if (!its.empty()) {
    nodes.reserve(2 * its.size());
    build_node(its, bounds, 0, static_cast<int>(its.size()));
    items = std::move(its);
    item_bounds = std::move(bounds);
  }
}

// Builds the subtree for its[first, first+count) and returns its node index: the split with the
// lowest surface-area-heuristic cost over the items sorted by centre along x, y and z.
int Renderer::Impl::build_node(std::vector<Item>& its, std::vector<Aabb>& bounds, int first, int count) {
  const int self = static_cast<int>(nodes.size());
  nodes.emplace_back();
  Aabb all;
  for (int i = first; i < first + count; ++i) all.add(bounds[static_cast<std::size_t>(i)]);
  for (int k = 0; k < 3; ++k) {
    nodes[static_cast<std::size_t>(self)].lo[k] = round_down(all.lo[k]);
    nodes[static_cast<std::size_t>(self)].hi[k] = round_up(all.hi[k]);
  }
  if (count <= 2) {
    nodes[static_cast<std::size_t>(self)].a = first;
    nodes[static_cast<std::size_t>(self)].b = count;
    return self;
  }
  // Surface-area heuristic over all splits of the items sorted by centre along each axis.
  auto area = [](const Aabb& a) {
    const Eigen::Vector3d e = (a.hi - a.lo).cwiseMax(0.0);
    return 2.0 * (e.x() * e.y() + e.y() * e.z() + e.z() * e.x());
  };
  const double parent_area = std::max(area(all), 1e-12);
  double best_cost = kInfinity;
  int best_axis = -1, best_split = 0;
  std::vector<int> order(static_cast<std::size_t>(count));
  std::vector<double> right_area(static_cast<std::size_t>(count));
  for (int axis = 0; axis < 3; ++axis) {
    std::iota(order.begin(), order.end(), first);
    std::sort(order.begin(), order.end(), [&](int a, int b) {
      const double ca = bounds[static_cast<std::size_t>(a)].centre()[axis];
      const double cb = bounds[static_cast<std::size_t>(b)].centre()[axis];
      return ca < cb || (ca == cb && a < b);
    });
    Aabb acc;
    for (int k = count - 1; k >= 1; --k) {
      acc.add(bounds[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])]);
      right_area[static_cast<std::size_t>(k)] = area(acc);
    }
    acc = Aabb{};
    for (int k = 1; k < count; ++k) {  // left = order[0, k)
      acc.add(bounds[static_cast<std::size_t>(order[static_cast<std::size_t>(k - 1)])]);
      const double cost = 1.0 + (area(acc) * k + right_area[static_cast<std::size_t>(k)] * (count - k)) / parent_area;
      if (cost < best_cost) {
        best_cost = cost;
        best_axis = axis;
        best_split = k;
      }
    }
  }
  if (count <= 8 && best_cost >= static_cast<double>(count)) {
    nodes[static_cast<std::size_t>(self)].a = first;
    nodes[static_cast<std::size_t>(self)].b = count;
    return self;
  }
  const int axis = best_axis;
  const int half = best_split;
  std::iota(order.begin(), order.end(), first);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const double ca = bounds[static_cast<std::size_t>(a)].centre()[axis];
    const double cb = bounds[static_cast<std::size_t>(b)].centre()[axis];
    return ca < cb || (ca == cb && a < b);
  });
  std::vector<Item> it2;
  std::vector<Aabb> b2;
  it2.reserve(order.size());
  b2.reserve(order.size());
  for (int k : order) {
    it2.push_back(its[static_cast<std::size_t>(k)]);
    b2.push_back(bounds[static_cast<std::size_t>(k)]);
  }
  std::copy(it2.begin(), it2.end(), its.begin() + first);
  std::copy(b2.begin(), b2.end(), bounds.begin() + first);
  build_node(its, bounds, first, half);  // the left child is node self + 1
  const int r = build_node(its, bounds, first + half, count - half);
  nodes[static_cast<std::size_t>(self)].a = r;
  nodes[static_cast<std::size_t>(self)].b = -1 - axis;
  return self;
}

void Renderer::Impl::set_eye(Frame& f, const Eigen::Vector3d& eye) const {
  f.eye = eye;
  f.roots.clear();
  for (Group& g : f.groups) {
    const Eigen::Vector3d c = g.bounds.centre() - eye;
    const double r = 0.5 * (g.bounds.hi - g.bounds.lo).norm() + 1e-6;
    const double dist = c.norm();
    if (dist <= r * 1.0001) {
      g.cos_max = -2.0;  // the eye is (nearly) inside: test every ray
      continue;
    }
    g.axis = c / dist;
    const double alpha = std::asin(r / dist) + 1e-9;
    g.cos_max = alpha >= std::numbers::pi / 2 ? -2.0 : std::cos(alpha) - 1e-12;
  }
  if (nodes.empty()) return;
  const float e[3] = {static_cast<float>(eye.x()), static_cast<float>(eye.y()), static_cast<float>(eye.z())};
  std::vector<std::pair<double, int>> found;
  std::vector<int> todo = {0};
  while (!todo.empty()) {
    const int ni = todo.back();
    todo.pop_back();
    const Node& n = nodes[static_cast<std::size_t>(ni)];
    double dist2 = 0.0;  // squared distance from the eye to the node's box
    for (int k = 0; k < 3; ++k) {
      const double dk = std::max({0.0, static_cast<double>(n.lo[k]) - e[k], static_cast<double>(e[k]) - n.hi[k]});
      dist2 += dk * dk;
    }
    // Strictly inside (with margin), an inner node is replaced by its children.
    bool inside = n.b < 0;
    for (int k = 0; k < 3 && inside; ++k) inside = n.lo[k] < e[k] - 1e-3f && e[k] + 1e-3f < n.hi[k];
    if (inside) {
      todo.push_back(ni + 1);
      todo.push_back(n.a);
    } else {
      found.emplace_back(dist2, ni);
    }
  }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) {
    return a.first > b.first || (a.first == b.first && a.second < b.second);
  });
  for (const auto& fd : found) f.roots.push_back(fd.second);
}

Frame Renderer::Impl::make_frame(double t, const Pose* cull_pose) const {
  Frame f;
  f.t = t;
  f.base.resize(scene.materials.size());
  for (std::size_t i = 0; i < scene.materials.size(); ++i) f.base[i] = scene.materials[i].base_at(t);
  Eigen::Vector3d eye = Eigen::Vector3d::Zero(), forward = Eigen::Vector3d::UnitZ();
  double cone = kInfinity;
  if (cull_pose) {
    eye = cull_pose->position;
    forward = cull_pose->orientation.normalized() * Eigen::Vector3d::UnitZ();
    cone = std::acos(std::clamp(cone_cos, -1.0, 1.0)) + 1e-3;
  }
  for (std::size_t m = 0; m < scene.motions.size(); ++m) {
    const auto& members = motion_boxes[m];
    if (members.empty()) continue;
    const Eigen::Isometry3d world_from_object = scene.motions[m](t);
    Group g;
    g.first = f.moving.size();
    for (std::size_t bi : members) {
      const Box& b = scene.boxes[bi];
      const Eigen::Isometry3d w = world_from_object * b.placement;
      g.bounds.add(box_bounds(w, b.lo, b.hi));
      f.moving.push_back(make_xbox(w, b, bi));
    }
    g.count = f.moving.size() - g.first;
    if (cull_pose && cone < 3.0) {
      const Eigen::Vector3d c = g.bounds.centre() - eye;
      const double r = 0.5 * (g.bounds.hi - g.bounds.lo).norm();
      const double dist = c.norm();
      if (dist > r) {
        const double theta = std::acos(std::clamp(c.dot(forward) / dist, -1.0, 1.0));
        const double alpha = std::asin(std::min(1.0, r / dist));
        if (theta - alpha > cone) {
          f.moving.resize(g.first);
          continue;
        }
      }
    }
    f.groups.push_back(g);
  }
  return f;
}

void Renderer::Impl::intersect_unbounded(const Eigen::Vector3d& o, const Eigen::Vector3d& d, Best& best) const {
  double u = 0.0, v = 0.0;
  for (std::size_t qi : unbounded_quads) {
    const Quad& q = scene.quads[qi];
    if (hit_quad(q, XQuad{qi, q.u_min, q.u_max, q.v_min, q.v_max}, quad_normals[qi], o, d, best.t, u, v)) {
      best.kind = RayHit::Kind::quad;
      best.index = qi;
      best.moving = false;
      best.u = u;
      best.v = v;
    }
  }
}

inline void Renderer::Impl::test_item(const Item& it, const RayD& r, Best& best) const {
  if (it.box) {
    int face = -1;
    const XBox& xb = sboxes[it.index];
    if (xb.aligned ? hit_aligned(xb, r, best.t, face) : hit_box(xb, r.o, r.d, best.t, face)) {
      best.kind = RayHit::Kind::box;
      best.index = it.index;
      best.moving = false;
      best.face = face;
    }
  } else {
    const XQuad& xq = xquads[it.index];
    double u = 0.0, v = 0.0;
    if (hit_quad(scene.quads[xq.index], xq, quad_normals[xq.index], r.o, r.d, best.t, u, v)) {
      best.kind = RayHit::Kind::quad;
      best.index = xq.index;
      best.moving = false;
      best.u = u;
      best.v = v;
    }
  }
}

void Renderer::Impl::intersect_bvh(const Frame& f, const RayD& r, Best& best) const {
  if (nodes.empty()) return;
  const RayF rf(r.o, r.d);
  constexpr int kStack = 256;
  int stack[kStack];
  int sp = 0;
  if (r.o == f.eye && !f.roots.empty() && f.roots.size() < kStack / 2) {
    for (int ni : f.roots) stack[sp++] = ni;
  } else {
    stack[sp++] = 0;
  }
  float tmax = std::isfinite(best.t) ? round_up(best.t) : std::numeric_limits<float>::max();
  while (sp > 0) {
    const int ni = stack[--sp];
    const Node& n = nodes[static_cast<std::size_t>(ni)];
    if (!hit_node(n, rf, tmax)) continue;
    if (n.b > 0) {
      const double before = best.t;
      for (int k = n.a; k < n.a + n.b; ++k) test_item(items[static_cast<std::size_t>(k)], r, best);
      if (best.t != before) tmax = round_up(best.t);
    } else if (sp + 2 <= kStack) {
      // Visit the nearer child first (pushed last).
      if (r.d[-1 - n.b] > 0.0) {
        stack[sp++] = n.a;
        stack[sp++] = ni + 1;
      } else {
        stack[sp++] = ni + 1;
        stack[sp++] = n.a;
      }
    }
  }
}

inline void Renderer::Impl::intersect_group(const Frame& f, const Group& g, const RayD& r, Best& best) const {
  if (!hit_aabb(g.bounds.lo, g.bounds.hi, r.o, r.inv, best.t)) return;
  for (std::size_t k = g.first; k < g.first + g.count; ++k) {
    int face = -1;
    if (hit_box(f.moving[k], r.o, r.d, best.t, face)) {
      best.kind = RayHit::Kind::box;
      best.index = k;
      best.moving = true;
      best.face = face;
    }
  }
}

void Renderer::Impl::intersect_moving(const Frame& f, const RayD& r, Best& best) const {
  const bool from_eye = r.o == f.eye;
  for (const Group& g : f.groups) {
    if (from_eye && r.d.dot(g.axis) < g.cos_max) continue;
    intersect_group(f, g, r, best);
  }
}

void Renderer::Impl::intersect(const Frame& f, const Eigen::Vector3d& o, const Eigen::Vector3d& d, Best& best) const {
  intersect_unbounded(o, d, best);
  const RayD r(o, d);
  intersect_bvh(f, r, best);
  intersect_moving(f, r, best);
}

// Candidate list of one image tile: the static items inside the tile's frustum (4 planes through
// the eye) and nearer than the farthest unbounded-quad hit of its rays, sorted by distance.
void Renderer::Impl::tile_candidates(const Frame& f, const Eigen::Matrix3d& r, const TilePlanes& tp, double dmax,
                                     std::vector<Candidate>& out, std::vector<std::size_t>& groups) const {
  out.clear();
  groups.clear();
  Eigen::Vector3d n[4];
  for (int k = 0; k < 4; ++k) n[k] = r * tp.n[k];
  const double dmax2 = std::isfinite(dmax) ? dmax * dmax : kInfinity;
  const Eigen::Vector3d& e = f.eye;
  // Lower bound of the distance from the eye to a box, and whether the frustum misses it.
  auto cull = [&](const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double& dist2) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d pv((n[k].x() >= 0 ? hi.x() : lo.x()) - e.x(), (n[k].y() >= 0 ? hi.y() : lo.y()) - e.y(),
                               (n[k].z() >= 0 ? hi.z() : lo.z()) - e.z());
      if (n[k].dot(pv) < 0.0) return true;
    }
    dist2 = (lo - e).cwiseMax(e - hi).cwiseMax(0.0).squaredNorm();
    return dist2 > dmax2;
  };
  for (std::size_t g = 0; g < f.groups.size(); ++g) {
    double d2 = 0.0;
    if (!cull(f.groups[g].bounds.lo, f.groups[g].bounds.hi, d2)) groups.push_back(g);
  }
  if (nodes.empty()) return;
  int stack[256];
  int sp = 0;
  if (!f.roots.empty() && f.roots.size() < 128) {
    for (int ni : f.roots) stack[sp++] = ni;
  } else {
    stack[sp++] = 0;
  }
  while (sp > 0) {
    const int ni = stack[--sp];
    const Node& nd = nodes[static_cast<std::size_t>(ni)];
    double dist2 = 0.0;
    const Eigen::Vector3d lo(nd.lo[0], nd.lo[1], nd.lo[2]), hi(nd.hi[0], nd.hi[1], nd.hi[2]);
    if (cull(lo, hi, dist2)) continue;
    if (nd.b > 0) {
      for (int k = nd.a; k < nd.a + nd.b; ++k) {
        const Aabb& ib = item_bounds[static_cast<std::size_t>(k)];
        double d2 = 0.0;
        if (cull(ib.lo, ib.hi, d2)) continue;
        out.push_back({std::sqrt(d2) - 1e-6, k});
        if (out.size() > kMaxCandidates) return;
      }
    } else if (sp + 2 <= 256) {
      stack[sp++] = nd.a;
      stack[sp++] = ni + 1;
    }
  }
  std::sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.dist < b.dist || (a.dist == b.dist && a.item < b.item);
  });
}

double Renderer::Impl::shade(const Frame& f, const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Best& best,
                             RayHit* out) const {
  if (best.kind == RayHit::Kind::sky) {
    const double t = scene.sky.temperature(d);
    if (out) {
      *out = RayHit{};
      out->surface_k = out->temperature_k = t;
    }
    return t;
  }
  SurfacePoint sp;
  std::size_t mat;
  std::size_t scene_index;
  if (best.kind == RayHit::Kind::quad) {
    const Quad& q = scene.quads[best.index];
    sp.p = Eigen::Vector3d(best.u, best.v, 0.0);
    sp.uv = Eigen::Vector2d(best.u, best.v);
    sp.face_size = Eigen::Vector2d(q.u_max - q.u_min, q.v_max - q.v_min);
    sp.face = -1;
    sp.object_seed = q.seed;
    mat = q.material;
    scene_index = best.index;
  } else {
    const XBox& xb = best.moving ? f.moving[best.index] : sboxes[best.index];
    const Box& b = scene.boxes[xb.index];
    const Eigen::Vector3d pl = (xb.r * (o + best.t * d) + xb.t).cwiseMax(xb.slo).cwiseMin(xb.shi);
    const int a = best.face / 2;
    const int i = a == 0 ? 1 : 0;
    const int j = a == 2 ? 1 : 2;
    sp.p = pl;
    sp.uv = Eigen::Vector2d(pl[i] - xb.slo[i], pl[j] - xb.slo[j]);
    sp.face_size = Eigen::Vector2d(xb.shi[i] - xb.slo[i], xb.shi[j] - xb.slo[j]);
    sp.face = best.face;
    sp.object_seed = b.seed;
    mat = b.material;
    scene_index = xb.index;
  }
  const double ts = scene.materials[mat].temperature_from_base(sp, f.base[mat]);
  double t = ts;
  const Atmosphere& atm = scene.atmosphere;
  if (std::isfinite(atm.extinction_length_m)) {
    const double tau = std::exp(-best.t / atm.extinction_length_m);
    t = ts * tau + atm.air_k * (1.0 - tau);
  }
  if (out) {
    out->kind = best.kind;
    out->index = scene_index;
    out->moving = best.moving;
    out->distance = best.t;
    out->point = o + best.t * d;
    out->surface = sp;
    out->surface_k = ts;
    out->temperature_k = t;
  }
  return t;
}

Renderer::Renderer(Scene scene, const Camera& camera, RenderOptions options) : impl_(std::make_unique<Impl>()) {
  camera.validate();
  scene.validate();
  if (options.supersample == 0 || options.supersample > 16)
    throw std::invalid_argument("renderer: supersample must be in 1..16");
  Impl& m = *impl_;
  m.scene = std::move(scene);
  m.camera = camera;
  m.options = options;
  m.threads = options.threads ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const unsigned ss = options.supersample;
  const std::size_t w = camera.width, h = camera.height;
  m.rays.resize(w * h * ss * ss);
  double cone_cos = 1.0;
  for (std::size_t y = 0; y < h; ++y)
    for (std::size_t x = 0; x < w; ++x)
      for (unsigned j = 0; j < ss; ++j)
        for (unsigned i = 0; i < ss; ++i) {
          const Eigen::Vector2d px(static_cast<double>(x) + (i + 0.5) / ss - 0.5,
                                   static_cast<double>(y) + (j + 0.5) / ss - 0.5);
          const Eigen::Vector3d r = camera.unproject(px);
          if (!r.allFinite() || !(r.z() > 0.0))
            throw std::invalid_argument("renderer: the camera's distortion cannot be inverted at pixel (" +
                                        std::to_string(px.x()) + ", " + std::to_string(px.y()) + ")");
          m.rays[(y * w + x) * ss * ss + j * ss + i] = r;
          cone_cos = std::min(cone_cos, r.z());
        }
  m.cone_cos = cone_cos;
  // Tile frusta: planes through the corner rays of each tile widened by one pixel, kept only if
  // every ray of the tile is inside (so a strong distortion can only cost speed).
  m.tiles_x = (w + kTile - 1) / kTile;
  const std::size_t tiles_y = (h + kTile - 1) / kTile;
  m.tiles.assign(m.tiles_x * tiles_y, TilePlanes{});
  for (std::size_t ty = 0; ty < tiles_y; ++ty) {
    for (std::size_t tx = 0; tx < m.tiles_x; ++tx) {
      const std::size_t x0 = tx * kTile, x1 = std::min(w, x0 + kTile), y0 = ty * kTile, y1 = std::min(h, y0 + kTile);
      const double u0 = static_cast<double>(x0) - 1.5, u1 = static_cast<double>(x1) + 0.5;
      const double v0 = static_cast<double>(y0) - 1.5, v1 = static_cast<double>(y1) + 0.5;
      const Eigen::Vector3d c[4] = {camera.unproject({u0, v0}), camera.unproject({u1, v0}), camera.unproject({u1, v1}),
                                    camera.unproject({u0, v1})};
      const Eigen::Vector3d centre = camera.unproject({0.5 * (u0 + u1), 0.5 * (v0 + v1)});
      TilePlanes tp;
      tp.valid = true;
      for (int k = 0; k < 4; ++k) {
        Eigen::Vector3d n = c[k].cross(c[(k + 1) % 4]);
        if (!(n.norm() > 1e-12)) tp.valid = false;
        n.normalize();
        if (n.dot(centre) < 0.0) n = -n;
        tp.n[k] = n;
      }
      for (std::size_t y = y0; y < y1 && tp.valid; ++y)
        for (std::size_t x = x0; x < x1 && tp.valid; ++x)
          for (std::size_t sub = 0; sub < std::size_t{ss} * ss; ++sub)
            for (int k = 0; k < 4; ++k)
              if (tp.n[k].dot(m.rays[(y * w + x) * ss * ss + sub]) < 1e-9) tp.valid = false;
      m.tiles[ty * m.tiles_x + tx] = tp;
    }
  }
  m.build();
}

Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;

void Renderer::render(const Pose& pose, double t, std::span<float> out) const {
  const Impl& m = *impl_;
  const std::size_t w = m.camera.width, h = m.camera.height;
  if (out.size() != w * h)
    throw std::invalid_argument("render: output has " + std::to_string(out.size()) + " pixels, the camera " +
                                std::to_string(w) + "x" + std::to_string(h));
  Frame f = m.make_frame(t, &pose);
  m.set_eye(f, pose.position);
  const Eigen::Matrix3d r = pose.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d o = pose.position;
  const unsigned ss = m.options.supersample;
  const std::size_t nsub = static_cast<std::size_t>(ss) * ss;
  const double norm = 1.0 / static_cast<double>(nsub);
  const std::size_t blocks = (h + kTile - 1) / kTile;  // a block = a row of tiles
  const unsigned n = static_cast<unsigned>(std::min<std::size_t>(m.threads, blocks));
  auto work = [&](unsigned k) {
    std::vector<Candidate> cands;
    cands.reserve(kMaxCandidates + 1);
    std::vector<std::size_t> tile_groups;
    std::vector<Best> bests(kTile * kTile * nsub);
    std::vector<Eigen::Vector3d> dirs(kTile * kTile * nsub);
    for (std::size_t b = k; b < blocks; b += n) {
      const std::size_t y0 = b * kTile, y1 = std::min(h, y0 + kTile);
      for (std::size_t tx = 0; tx < m.tiles_x; ++tx) {
        const std::size_t x0 = tx * kTile, x1 = std::min(w, x0 + kTile);
        // Pass 1: directions and the unbounded planes (ground), whose farthest hit bounds the tile.
        double dmax = 0.0;
        std::size_t i = 0;
        for (std::size_t y = y0; y < y1; ++y)
          for (std::size_t x = x0; x < x1; ++x)
            for (std::size_t s = 0; s < nsub; ++s, ++i) {
              dirs[i] = r * m.rays[(y * w + x) * nsub + s];
              bests[i] = Best{};
              m.intersect_unbounded(o, dirs[i], bests[i]);
              dmax = std::max(dmax, bests[i].t);
            }
        const TilePlanes& tp = m.tiles[b * m.tiles_x + tx];
        bool use_list = false;
        if (tp.valid) {
          m.tile_candidates(f, r, tp, dmax, cands, tile_groups);
          use_list = cands.size() <= kMaxCandidates;
        }
        // Pass 2: static items (tile list or BVH), moving boxes, shading.
        i = 0;
        for (std::size_t y = y0; y < y1; ++y)
          for (std::size_t x = x0; x < x1; ++x) {
            double acc = 0.0;
            for (std::size_t s = 0; s < nsub; ++s, ++i) {
              Best& best = bests[i];
              const RayD rd(o, dirs[i]);
              if (use_list) {
                for (const Candidate& c : cands) {
                  if (c.dist >= best.t) break;
                  m.test_item(m.items[static_cast<std::size_t>(c.item)], rd, best);
                }
              } else {
                m.intersect_bvh(f, rd, best);
              }
              if (tp.valid) {
                for (std::size_t g : tile_groups) m.intersect_group(f, f.groups[g], rd, best);
              } else {
                m.intersect_moving(f, rd, best);
              }
              acc += m.shade(f, o, dirs[i], best, nullptr);
            }
            out[y * w + x] = static_cast<float>(acc * norm);
          }
      }
    }
  };
  if (n <= 1) {
    work(0);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(n - 1);
  for (unsigned k = 1; k < n; ++k) pool.emplace_back(work, k);
  work(0);
  for (auto& th : pool) th.join();
}

std::vector<float> Renderer::render(const Pose& pose, double t) const {
  std::vector<float> out(static_cast<std::size_t>(impl_->camera.width) * impl_->camera.height);
  render(pose, t, out);
  return out;
}

RayHit Renderer::trace(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, double t) const {
  if (!(direction.norm() > 0.0)) throw std::invalid_argument("trace: zero direction");
  const double n = direction.norm();
  // Unit directions pass unchanged, so trace_pixel() reproduces render() bit for bit.
  const Eigen::Vector3d d = std::abs(n - 1.0) < 1e-12 ? direction : Eigen::Vector3d(direction / n);
  Frame f = impl_->make_frame(t, nullptr);
  impl_->set_eye(f, origin);
  Best best;
  impl_->intersect(f, origin, d, best);
  RayHit hit;
  impl_->shade(f, origin, d, best, &hit);
  return hit;
}

RayHit Renderer::trace_pixel(const Pose& pose, double t, const Eigen::Vector2d& pixel) const {
  const Eigen::Matrix3d r = pose.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d d = r * impl_->camera.unproject(pixel);
  return trace(pose.position, d, t);
}

const Scene& Renderer::scene() const { return impl_->scene; }
const Camera& Renderer::camera() const { return impl_->camera; }
const RenderOptions& Renderer::options() const { return impl_->options; }

}  // namespace bolo::sim::scene
