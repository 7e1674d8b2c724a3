#pragma once
// TreeBuilder's Builder, its first steps: the mesh copied, the faces kept (non-degenerate) with
// their normals and corner angles (or taken from the region cache), the topology: opposite
// half-edges, valences, angle-weighted vertex pseudo-normals.
// Included by tree_builder.cpp only, after Builder's class: the builder compiles as one
// translation unit, as it did when it was one file, so the compiler inlines across its parts
// exactly as before (the object code is the same).
namespace cathbox::collision {
namespace {

inline void Builder::copy_mesh() {
  d_.positions.resize(mesh_.positions_mm.size());
  glm::dvec3 max_abs{0.0};
  for (std::size_t i = 0; i < d_.positions.size(); ++i) {
    d_.positions[i] = glm::dvec3(mesh_.positions_mm[i]);
    max_abs = glm::max(max_abs, glm::abs(d_.positions[i]));
  }
  d_.scale_mm = max_abs.x + max_abs.y + max_abs.z;
  d_.triangles = mesh_.triangles;
  d_.regions = mesh_.triangle_regions;
}

// Faces with the cache: every region's triangles (degenerate ones too) in mesh order, and the
// cached region holding the same floats in the same order, if any; a face of such a region
// takes its FaceFacts from there.
inline void Builder::match_cache() {
  if (cache_ == nullptr) return;
  const std::size_t n = mesh_.triangle_count();
  std::unordered_map<std::uint64_t, std::uint32_t> index;
  std::vector<std::uint32_t> region_of(n);
  std::vector<std::uint32_t> first(1, 0);
  std::uint64_t last_key = ~0ull;
  std::uint32_t last = 0;
  for (std::size_t f = 0; f < n; ++f) {
    const std::uint64_t key = region_key(d_.regions[f]);
    if (key != last_key) {
      auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(all_keys_.size()));
      if (inserted) {
        all_keys_.push_back(d_.regions[f]);
        first.push_back(0);
      }
      last_key = key;
      last = it->second;
    }
    region_of[f] = last;
    ++first[last + 1];
  }
  for (std::size_t r = 0; r + 1 < first.size(); ++r) first[r + 1] += first[r];
  std::vector<std::uint32_t> faces(n);
  std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
  for (std::uint32_t f = 0; f < n; ++f) faces[fill[region_of[f]]++] = f;
  all_corners_.assign(all_keys_.size(), {});
  all_hit_.assign(all_keys_.size(), -1);
  source_.assign(n, nullptr);
  for (std::size_t r = 0; r < all_keys_.size(); ++r) {
    std::vector<glm::vec3>& corners = all_corners_[r];
    corners.reserve(3 * std::size_t{first[r + 1] - first[r]});
    for (std::uint32_t i = first[r]; i < first[r + 1]; ++i)
      for (std::uint32_t k = 0; k < 3; ++k) corners.push_back(mesh_.positions_mm[d_.triangles[3 * faces[i] + k]]);
    for (std::size_t c = 0; c < cache_->regions.size(); ++c) {
      const CachedRegion& cached = cache_->regions[c];
      if (cached.region == all_keys_[r] && cached.corners.size() == corners.size() &&
          std::memcmp(cached.corners.data(), corners.data(), corners.size() * sizeof(glm::vec3)) == 0) {
        all_hit_[r] = static_cast<std::int32_t>(c);
        break;
      }
    }
    if (all_hit_[r] < 0) continue;
    const std::vector<FaceFacts>& facts = cache_->regions[static_cast<std::size_t>(all_hit_[r])].facts;
    for (std::uint32_t i = first[r]; i < first[r + 1]; ++i) source_[faces[i]] = &facts[i - first[r]];
    hit_of_key_[region_key(all_keys_[r])] = all_hit_[r];
  }
  all_first_ = std::move(first);
  all_faces_ = std::move(faces);
}

// Kept (non-degenerate) faces in mesh order, their unit normals and corner angles: computed,
// or taken from the cache for the faces of unchanged regions (the same values: they depend on
// the corners only).
inline void Builder::find_kept_faces() {
  const std::size_t n = mesh_.triangle_count();
  d_.face_normals.resize(n);
  facts_.reserve(n);
  kept_.reserve(n);
  for (std::uint32_t f = 0; f < n; ++f) {
    facts_.push_back(!source_.empty() && source_[f] != nullptr ? *source_[f] : face_facts(f));
    d_.face_normals[f] = facts_.back().normal;
    if (facts_.back().kept) kept_.push_back(f);
  }
}

inline FaceFacts Builder::face_facts(std::uint32_t f) const {
  FaceFacts facts;
  const glm::dvec3 a = corner(f, 0);
  const glm::dvec3 b = corner(f, 1);
  const glm::dvec3 c = corner(f, 2);
  const glm::dvec3 cr = glm::cross(b - a, c - a);
  const double area2 = glm::length(cr);
  const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a),
                                   glm::dot(c - b, c - b)});
  if (!(area2 > 1e-12 * longest)) return facts;
  facts.kept = true;
  facts.normal = cr / area2;
  const glm::dvec3 p[3] = {a, b, c};
  const glm::dvec3 e[3] = {p[1] - p[0], p[2] - p[1], p[0] - p[2]};  // e[k] leaves corner k
  // The largest angle (opposite the longest edge) is pi minus the other two, which atan2
  // gives accurately even for slivers; float precision is plenty for a weight.
  double len[3];
  for (int k = 0; k < 3; ++k) len[k] = glm::dot(e[k], e[k]);
  const int longest_edge = len[0] >= len[1] && len[0] >= len[2] ? 0 : (len[1] >= len[2] ? 1 : 2);
  const int big = (longest_edge + 2) % 3;  // the corner opposite the longest edge
  double sum = 0.0;
  for (int k = 0; k < 3; ++k) {
    if (k == big) continue;
    const glm::dvec3 u = e[k];
    const glm::dvec3 v = -e[(k + 2) % 3];
    facts.angle[k] = std::atan2(static_cast<float>(glm::length(glm::cross(u, v))), static_cast<float>(glm::dot(u, v)));
    sum += facts.angle[k];
  }
  facts.angle[big] = std::max(0.0, 3.14159265358979323846 - sum);
  return facts;
}

// Vertex -> kept triangles, neighbours across edges, valences, pseudo-normals.
inline void Builder::build_topology() {
  const VertexHalfEdges edges = outgoing_half_edges();
  const std::size_t nv = d_.positions.size();
  d_.valence.resize(nv);
  for (std::size_t v = 0; v < nv; ++v) d_.valence[v] = edges.start[v + 1] - edges.start[v];
  link_opposites(edges);
  accumulate_vertex_normals();
}

inline Builder::VertexHalfEdges Builder::outgoing_half_edges() const {
  const std::size_t nv = d_.positions.size();
  VertexHalfEdges e;
  e.start.assign(nv + 1, 0);
  for (std::uint32_t f : kept_)
    for (int k = 0; k < 3; ++k) ++e.start[d_.triangles[3 * f + k] + 1];
  for (std::size_t v = 0; v < nv; ++v) e.start[v + 1] += e.start[v];
  e.out.resize(e.start[nv]);
  std::vector<std::uint32_t> fill(e.start.begin(), e.start.end() - 1);
  for (std::uint32_t f : kept_)
    for (int k = 0; k < 3; ++k)
      e.out[fill[d_.triangles[3 * f + k]]++] = {d_.triangles[3 * f + (k + 1) % 3], f};
  return e;
}

// The opposite of u -> w is w -> u; another u -> w means a non-manifold or flipped face.
inline void Builder::link_opposites(const VertexHalfEdges& edges) {
  const auto& start = edges.start;
  const auto& out = edges.out;
  d_.opposite.assign(d_.triangles.size(), -1);
  bool closed = true;
  bool oriented = true;
  for (std::uint32_t f : kept_) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t u = d_.triangles[3 * f + k];
      const std::uint32_t w = d_.triangles[3 * f + (k + 1) % 3];
      int found = 0;
      for (std::uint32_t i = start[w]; i < start[w + 1]; ++i) {
        if (out[i].to != u) continue;
        if (found++ == 0) d_.opposite[3 * f + k] = static_cast<std::int32_t>(out[i].face);
      }
      for (std::uint32_t i = start[u]; i < start[u + 1]; ++i) {
        if (out[i].to != w || out[i].face == f) continue;
        oriented = false;
        if (found++ == 0) d_.opposite[3 * f + k] = static_cast<std::int32_t>(out[i].face);
      }
      if (found != 1) closed = false;
    }
  }
  d_.stats.closed = closed;
  d_.stats.consistently_oriented = oriented;
}

// Angle-weighted pseudo-normals of the vertices.
inline void Builder::accumulate_vertex_normals() {
  d_.vertex_normals.assign(d_.positions.size(), glm::dvec3{0.0});
  for (std::uint32_t f : kept_) {
    for (int k = 0; k < 3; ++k) d_.vertex_normals[d_.triangles[3 * f + k]] += facts_[f].angle[k] * d_.face_normals[f];
  }
  for (glm::dvec3& n : d_.vertex_normals) {
    const double len = glm::length(n);
    if (len > 0.0) n /= len;
  }
}

}  // namespace
}  // namespace cathbox::collision
