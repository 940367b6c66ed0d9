#include "body_detector.hpp"

#include "surface_patch.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <lista/parallel.hpp>
#include <lista_geometry/range_image.hpp>
#include <lista_geometry/voxel_key.hpp>

namespace lista::filter {

using geometry::RangeImage;

namespace {

// Empty scans (a dropout, a scan io.missions did not read) neither count
// nor witness.
bool holds_points(const Scan& s) { return s.points && !s.points->empty(); }

// Up to `count` scans between witness_min and witness_max from scan i,
// nearest in scan order, looking both ways in turn.
std::vector<size_t> witnesses_of(const Mission& m, size_t i, const BodyConfig& c) {
  std::vector<size_t> out;
  const Eigen::Vector3d at = m.scans[i].pose.translation();
  const size_t n = m.scans.size();
  for (size_t step = 1; step < n && int(out.size()) < c.witnesses; ++step)
    for (const long j : {long(i) - long(step), long(i + step)}) {
      if (j < 0 || j >= long(n) || int(out.size()) >= c.witnesses || !holds_points(m.scans[size_t(j)])) continue;
      const double d = (m.scans[size_t(j)].pose.translation() - at).norm();
      if (d >= c.witness_min && d <= c.witness_max) out.push_back(size_t(j));
    }
  return out;
}

// Sensor-frame cells within max_range and how many of the `scans` occupy
// each, sorted by key.
std::vector<std::pair<uint64_t, uint32_t>> occupancy(const std::vector<const PointSet*>& scans, const BodyConfig& c,
                                                     int threads) {
  const size_t n = scans.size();
  const float r2 = float(c.max_range * c.max_range);
  std::vector<std::vector<uint64_t>> per_scan(n);
  parallel_for(n, threads, [&](size_t h) {
    std::vector<uint64_t>& keys = per_scan[h];
    for (const auto& p : scans[h]->xyz)
      if (p.squaredNorm() < r2) keys.push_back(cell_key(p, c.cell));
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
  });
  std::vector<uint64_t> all;
  for (auto& keys : per_scan) {
    all.insert(all.end(), keys.begin(), keys.end());
    std::vector<uint64_t>().swap(keys);
  }
  std::sort(all.begin(), all.end());
  std::vector<std::pair<uint64_t, uint32_t>> counts;  // sorted by key
  for (size_t a = 0; a < all.size();) {
    size_t b = a;
    while (b < all.size() && all[b] == all[a]) ++b;
    counts.emplace_back(all[a], uint32_t(b - a));
    a = b;
  }
  return counts;
}

// Cells occupied in min_share of the scans are candidates (`core`); those
// occupied in a quarter as many are checked too, and go with a confirmed
// candidate they touch (a body surface noisier than a cell spreads over its
// neighbours, each occupied less often). `cells` sorted.
struct Candidates {
  std::vector<uint64_t> cells;
  std::vector<char> core;
};

Candidates candidate_cells(const std::vector<std::pair<uint64_t, uint32_t>>& counts, size_t n, const BodyConfig& c,
                           BodyCells& out, uint32_t at_least = 1) {
  Candidates cs;
  const uint32_t need = std::max(at_least, uint32_t(std::ceil(c.min_share * double(n))));
  const uint32_t need_fringe = std::max<uint32_t>(1, uint32_t(std::ceil(c.min_share * double(n) / 4.0)));
  for (const auto& [key, k] : counts)
    if (k >= need_fringe) {
      cs.cells.push_back(key);
      cs.core.push_back(k >= need);
      out.candidates += k >= need;
    }
  return cs;
}

// The witnesses' votes on each candidate, summed over probe scans spread
// over the mission (`see`: saw through it, `present`: saw it there).
struct Votes {
  std::vector<int> see, present;
};

// Probe scans spread over the mission; each probe's candidate cells are
// placed in the map by their centroid and looked at from its witnesses.
// Empty votes when no probe has witnesses.
Votes witness_votes(const Mission& m, const std::vector<size_t>& held, const std::vector<uint64_t>& candidates,
                    const BodyConfig& c, int threads, BodyCells& out) {
  const size_t n = held.size();
  const float r2 = float(c.max_range * c.max_range);
  const size_t probes = std::min<size_t>(n, size_t(std::max(1, c.probes)));
  std::vector<size_t> probe_scans;
  std::vector<std::vector<size_t>> probe_witnesses;
  for (size_t k = 0; k < probes; ++k) {
    const size_t i = held[size_t((double(k) + 0.5) * double(n) / double(probes))];
    std::vector<size_t> witnesses = witnesses_of(m, i, c);
    if (witnesses.empty()) continue;
    probe_scans.push_back(i);
    probe_witnesses.push_back(std::move(witnesses));
  }
  out.checked = !probe_scans.empty();
  std::vector<int> see(candidates.size(), 0), present(candidates.size(), 0);
  if (candidates.empty() || probe_scans.empty()) return {};

  // Every witness's range image, built once.
  std::vector<size_t> witness_scans;
  for (const auto& w : probe_witnesses) witness_scans.insert(witness_scans.end(), w.begin(), w.end());
  std::sort(witness_scans.begin(), witness_scans.end());
  witness_scans.erase(std::unique(witness_scans.begin(), witness_scans.end()), witness_scans.end());
  std::vector<std::unique_ptr<RangeImage>> images(witness_scans.size());
  parallel_for(witness_scans.size(), threads,
               [&](size_t w) { images[w] = std::make_unique<RangeImage>(*m.scans[witness_scans[w]].points); });
  const auto image_of = [&](size_t scan) -> const RangeImage& {
    return *images[size_t(std::lower_bound(witness_scans.begin(), witness_scans.end(), scan) - witness_scans.begin())];
  };

  // Votes per probe (then summed in probe order, so threads change nothing).
  std::vector<std::vector<int8_t>> votes(probe_scans.size());
  parallel_for(probe_scans.size(), threads, [&](size_t k) {
    const Scan& scan = m.scans[probe_scans[k]];
    std::vector<std::pair<uint64_t, Eigen::Vector3f>> keyed;
    for (const auto& p : scan.points->xyz)
      if (p.squaredNorm() < r2) keyed.emplace_back(cell_key(p, c.cell), p);
    std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    std::vector<Patch> patches(candidates.size());
    for (size_t ci = 0; ci < candidates.size(); ++ci) patches[ci] = patch_of(keyed, candidates[ci]);
    std::vector<int8_t>& v = votes[k];
    v.assign(candidates.size() * probe_witnesses[k].size(), 0);
    for (size_t w = 0; w < probe_witnesses[k].size(); ++w) {
      const size_t j = probe_witnesses[k][w];
      const RangeImage& image = image_of(j);
      const Eigen::Isometry3d sensor_j_from_i = m.scans[j].pose.inverse() * scan.pose;
      for (size_t ci = 0; ci < candidates.size(); ++ci) {
        if (!patches[ci].valid) continue;
        const Eigen::Vector3d centre = sensor_j_from_i * patches[ci].centre;
        const Eigen::Vector3d normal = sensor_j_from_i.linear() * patches[ci].normal;
        const RangeImage::Vote vote = image.look(centre, normal, c.depth, c.cell, c.margin);
        v[w * candidates.size() + ci] = vote == RangeImage::Vote::present ? 1 : vote == RangeImage::Vote::see_through ? -1 : 0;
      }
    }
  });
  for (const auto& v : votes)
    for (size_t x = 0; x < v.size(); ++x) {
      const size_t ci = x % candidates.size();
      present[ci] += v[x] > 0;
      see[ci] += v[x] < 0;
    }

  return {std::move(see), std::move(present)};
}

// Confirmed: a candidate most of whose (at least min_votes) votes see
// through it. The body is what is connected to a confirmed cell: cells
// occupied in min_share of the scans are followed, less often occupied
// ones taken where they touch (a surface noisier than a cell spreads over
// its neighbours), and a cell whose votes say present stops it. Body
// edges and corners have no single normal and so no votes of their own.
void grow_body(const Candidates& cs, const Votes& tally, const BodyConfig& c, BodyCells& out) {
  const std::vector<uint64_t>& candidates = cs.cells;
  const std::vector<char>& core = cs.core;
  const std::vector<int>& see = tally.see;
  const std::vector<int>& present = tally.present;
  std::vector<char> blocked(candidates.size(), 0), in_body(candidates.size(), 0);
  std::vector<size_t> queue;
  for (size_t ci = 0; ci < candidates.size(); ++ci) {
    const int votes = see[ci] + present[ci];
    const bool enough = votes >= c.min_votes;
    const bool through = double(see[ci]) >= c.see_through_share * double(votes);
    blocked[ci] = enough && !through;
    out.voted += core[ci] && enough;
    if (core[ci] && enough && through) {
      ++out.confirmed;
      in_body[ci] = 1;
      queue.push_back(ci);
    }
  }
  while (!queue.empty()) {
    const size_t ci = queue.back();
    queue.pop_back();
    out.drop.push_back(candidates[ci]);
    if (!core[ci]) continue;  // less often occupied cells are taken, not followed
    const Eigen::Vector3i at = geometry::voxel_of_key(candidates[ci]);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const uint64_t key = geometry::voxel_key(at + Eigen::Vector3i(dx, dy, dz));
          const auto it = std::lower_bound(candidates.begin(), candidates.end(), key);
          if (it == candidates.end() || *it != key) continue;
          const size_t nb = size_t(it - candidates.begin());
          if (in_body[nb] || blocked[nb]) continue;
          in_body[nb] = 1;
          queue.push_back(nb);
        }
  }
}

}  // namespace

uint64_t cell_key(const Eigen::Vector3f& p, double cell) { return geometry::voxel_key_of(p.cast<double>(), cell); }

BodyCells find_body_cells(const Mission& m, const BodyConfig& c, int threads) {
  BodyCells out;
  std::vector<size_t> held;
  for (size_t s = 0; s < m.scans.size(); ++s)
    if (holds_points(m.scans[s])) held.push_back(s);
  const size_t n = held.size();
  out.scans = n;
  if (int(n) < c.min_scans || c.max_range <= 0) return out;
  std::vector<const PointSet*> scans;
  for (const size_t s : held) scans.push_back(m.scans[s].points.get());
  const Candidates cs = candidate_cells(occupancy(scans, c, threads), n, c, out);
  const Votes votes = witness_votes(m, held, cs.cells, c, threads, out);
  if (votes.see.empty()) return out;
  grow_body(cs, votes, c, out);
  std::sort(out.drop.begin(), out.drop.end());  // each cell went in once (in_body)
  return out;
}

BodyCells find_station_body_cells(const std::vector<const PointSet*>& stations, const BodyConfig& c, int threads) {
  BodyCells out;
  std::vector<const PointSet*> held;
  for (const PointSet* s : stations)
    if (s && !s->empty()) held.push_back(s);
  out.scans = held.size();
  if (held.size() < 2 || c.max_range <= 0) return out;
  out.checked = true;
  const Candidates cs = candidate_cells(occupancy(held, c, threads), held.size(), c, out, 2);
  for (size_t ci = 0; ci < cs.cells.size(); ++ci)
    if (cs.core[ci]) out.drop.push_back(cs.cells[ci]);
  out.confirmed = out.candidates;
  return out;  // cs.cells is sorted, so is drop
}

size_t drop_body_points(Mission& m, const BodyCells& cells, const BodyConfig& c, int threads) {
  if (cells.drop.empty()) return 0;
  const float r2 = float(c.max_range * c.max_range);
  std::vector<size_t> dropped(m.scans.size(), 0);
  parallel_for(m.scans.size(), threads, [&](size_t s) {
    Scan& scan = m.scans[s];
    if (!scan.points) return;
    const PointSet& all = *scan.points;
    std::vector<uint32_t> keep;
    keep.reserve(all.size());
    for (size_t i = 0; i < all.size(); ++i) {
      const auto& p = all.xyz[i];
      if (p.squaredNorm() >= r2 || !std::binary_search(cells.drop.begin(), cells.drop.end(), cell_key(p, c.cell)))
        keep.push_back(uint32_t(i));
    }
    if (keep.size() == all.size()) return;
    dropped[s] = all.size() - keep.size();
    scan.points = std::make_shared<PointSet>(all.select(keep));
  });
  size_t total = 0;
  for (const size_t d : dropped) total += d;
  return total;
}

}  // namespace lista::filter
