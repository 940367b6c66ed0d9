#include "ring_key_index.hpp"

#include <lista/error.hpp>

#include <flann/flann.hpp>

namespace lista::align {

struct RingKeyIndex::Impl {
  std::vector<float> data;
  std::unique_ptr<flann::Index<flann::L2<float>>> index;
};

RingKeyIndex::RingKeyIndex(const std::vector<Eigen::VectorXf>& keys) : impl_(std::make_unique<Impl>()) {
  count_ = keys.size();
  if (count_ == 0) return;
  dim_ = static_cast<size_t>(keys.front().size());
  impl_->data.reserve(count_ * dim_);
  for (const auto& k : keys) {
    if (static_cast<size_t>(k.size()) != dim_) throw Error("ring keys of different lengths");
    impl_->data.insert(impl_->data.end(), k.data(), k.data() + dim_);
  }
  flann::Matrix<float> matrix(impl_->data.data(), count_, dim_);
  impl_->index = std::make_unique<flann::Index<flann::L2<float>>>(matrix, flann::KDTreeSingleIndexParams(10));
  impl_->index->buildIndex();
}

RingKeyIndex::~RingKeyIndex() = default;

std::vector<size_t> RingKeyIndex::nearest(const Eigen::VectorXf& key, size_t k) const {
  if (count_ == 0 || k == 0) return {};
  if (static_cast<size_t>(key.size()) != dim_) throw Error("ring key length does not match the index");
  k = std::min(k, count_);
  std::vector<float> query(key.data(), key.data() + dim_);
  std::vector<size_t> indices(k);
  std::vector<float> dists(k);
  flann::Matrix<float> q(query.data(), 1, dim_);
  flann::Matrix<size_t> idx(indices.data(), 1, k);
  flann::Matrix<float> d(dists.data(), 1, k);
  flann::SearchParams params(-1);  // exact search in the single-tree index
  params.cores = 1;
  impl_->index->knnSearch(q, idx, d, k, params);
  return indices;
}

}  // namespace lista::align
