#include <lista_objfeat/descriptor_net.hpp>
#include <lista_objfeat/sha256.hpp>

#include <lista/error.hpp>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace lista::objfeat {
namespace {

constexpr char kMagic[8] = {'L', 'I', 'S', 'T', 'A', 'D', 'N', '2'};
constexpr char kMagicFirst[8] = {'L', 'I', 'S', 'T', 'A', 'D', 'N', '1'};

void put_u32(std::string& s, uint32_t v) { s.append(reinterpret_cast<const char*>(&v), 4); }

struct Reader {
  const std::string& buf;
  size_t pos = 0;
  const std::string& path;
  void need(size_t n) {
    if (pos + n > buf.size()) throw Error("model weights '" + path + "' are truncated");
  }
  uint32_t u32() {
    need(4);
    uint32_t v;
    std::memcpy(&v, buf.data() + pos, 4);
    pos += 4;
    return v;
  }
};

}  // namespace

DescriptorNetImpl::DescriptorNetImpl(const NetConfig& c) : config(c) {
  l1 = register_module("l1", torch::nn::Linear(c.in, c.w1));
  l2 = register_module("l2", torch::nn::Linear(c.w1, c.w2));
  l3 = register_module("l3", torch::nn::Linear(c.w2, c.w3));
  h1 = register_module("h1", torch::nn::Linear(2 * c.w3 + c.globals, c.head));
  h2 = register_module("h2", torch::nn::Linear(c.head, c.out));
}

torch::Tensor DescriptorNetImpl::forward(const torch::Tensor& x, const torch::Tensor& g) {
  auto f = torch::relu(l1(x));
  f = torch::relu(l2(f));
  f = l3(f);
  auto pooled = config.globals > 0 ? torch::cat({std::get<0>(f.max(1)), f.mean(1), g}, 1)
                                   : torch::cat({std::get<0>(f.max(1)), f.mean(1)}, 1);
  auto d = h2(torch::relu(h1(pooled)));
  return torch::nn::functional::normalize(d, torch::nn::functional::NormalizeFuncOptions().dim(1).eps(1e-8));
}

CanonicalConfig canonical_config(const NetConfig& c, uint64_t seed) {
  CanonicalConfig cc;
  cc.points = c.points;
  cc.grid = c.grid;
  cc.seed = seed;
  cc.frame = c.frame;
  cc.floor = c.floor;
  return cc;
}

torch::Tensor describe_clouds(DescriptorNet& net, const std::vector<CanonicalCloud>& clouds, size_t begin, size_t end) {
  const NetConfig& c = net->config;
  const long n = long(end - begin);
  torch::Tensor x = torch::empty({n, c.points, c.in});
  torch::Tensor g = torch::empty({n, std::max(c.globals, 1)});
  if (c.in > kCanonicalChannels) throw Error("describe_clouds: the network reads more channels than canonical.hpp makes");
  for (size_t i = begin; i < end; ++i) {
    const CanonicalCloud& cc = clouds[i];
    if (cc.points != c.points || cc.features.size() != size_t(c.points) * size_t(kCanonicalChannels))
      throw Error("describe_clouds: a cloud was not made with the network's canonical configuration");
    // The first c.in channels of every point.
    float* dst = x.data_ptr<float>() + (i - begin) * size_t(c.points * c.in);
    for (int p = 0; p < c.points; ++p)
      std::copy_n(cc.features.begin() + ptrdiff_t(p) * kCanonicalChannels, c.in, dst + ptrdiff_t(p) * c.in);
    if (c.globals > 0)
      std::copy_n(cc.globals.begin(), c.globals, g.data_ptr<float>() + (i - begin) * size_t(c.globals));
  }
  return net->forward(x, g);
}

torch::Tensor mean_of_samples(const torch::Tensor& rows, int samples) {
  if (samples <= 1) return rows.contiguous();
  torch::Tensor mean = rows.reshape({rows.size(0) / samples, samples, rows.size(1)}).mean(1);
  return torch::nn::functional::normalize(mean, torch::nn::functional::NormalizeFuncOptions().dim(1).eps(1e-8))
      .contiguous();
}

void save_weights(DescriptorNet& net, const std::string& path) {
  const NetConfig& c = net->config;
  std::string buf(kMagic, 8);
  for (int v : {c.points, c.grid, c.in, c.w1, c.w2, c.w3, c.head, c.out, int(c.frame), c.globals, int(c.floor)})
    put_u32(buf, uint32_t(v));
  auto params = net->named_parameters();
  put_u32(buf, uint32_t(params.size()));
  for (const auto& p : params) {
    put_u32(buf, uint32_t(p.key().size()));
    buf += p.key();
    torch::Tensor t = p.value().detach().to(torch::kFloat32).contiguous();
    if (!torch::isfinite(t).all().item<bool>())
      throw Error("the network's tensor '" + p.key() + "' holds NaN or infinite values (training diverged); nothing written");
    put_u32(buf, uint32_t(t.numel()));
    buf.append(reinterpret_cast<const char*>(t.data_ptr<float>()), size_t(t.numel()) * 4);
  }
  // Both files are written under temporary names first and renamed only when
  // both exist, so a failure leaves neither a .tmp nor a half-replaced pair.
  const std::string tmp = path + ".tmp", sidecar_tmp = path + ".sha256.tmp";
  auto write = [](const std::string& file, const std::string& data) {
    std::ofstream out(file, std::ios::binary);
    out.write(data.data(), std::streamsize(data.size()));
    if (!out) throw Error("cannot write '" + file + "'");
  };
  std::error_code ec;
  try {
    write(tmp, buf);
    write(sidecar_tmp, sha256_hex(buf) + "  " + std::filesystem::path(path).filename().string() + "\n");
    std::filesystem::rename(tmp, path);
    std::filesystem::rename(sidecar_tmp, path + ".sha256");
  } catch (const std::filesystem::filesystem_error& e) {
    std::filesystem::remove(tmp, ec);
    std::filesystem::remove(sidecar_tmp, ec);
    throw Error("cannot put the weights at '" + path + "': " + e.code().message());
  } catch (...) {
    std::filesystem::remove(tmp, ec);
    std::filesystem::remove(sidecar_tmp, ec);
    throw;
  }
}

DescriptorNet load_weights(const std::string& path, std::string* sha256) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec))
    throw Error("model weights '" + path + "' is a folder; give the weights file (e.g. <folder>/describe-learned.bin)");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw Error("model weights '" + path + "' not found (set the 'weights' parameter or LISTA_MODEL_DIR)");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string buf = ss.str();

  std::ifstream sum_in(path + ".sha256");
  std::string expected;
  if (!(sum_in >> expected))
    throw Error("checksum file '" + path + ".sha256' is missing or empty; cannot trust the weights");
  const std::string actual = sha256_hex(buf);
  if (actual != expected)
    throw Error("model weights '" + path + "' are corrupt: SHA-256 does not match '" + path + ".sha256'");
  if (sha256) *sha256 = actual;

  const bool first = buf.size() >= 8 && std::memcmp(buf.data(), kMagicFirst, 8) == 0;
  if (buf.size() < 8 || (!first && std::memcmp(buf.data(), kMagic, 8) != 0))
    throw Error("'" + path + "' is not a LiSTA descriptor weights file (bad magic)");
  Reader r{buf, 8, path};
  NetConfig c;
  int* fields[] = {&c.points, &c.grid, &c.in, &c.w1, &c.w2, &c.w3, &c.head, &c.out};
  for (int* f : fields) {
    uint32_t v = r.u32();
    if (v == 0 || v > 65536) throw Error("model weights '" + path + "' have an invalid configuration");
    *f = int(v);
  }
  c.frame = YawFrame::principal_axis;
  c.globals = 0;
  if (!first) {
    const uint32_t frame = r.u32(), globals = r.u32();
    if (frame > uint32_t(YawFrame::bounding_rectangle) || !valid_global_count(int(globals)))
      throw Error("model weights '" + path + "' have an invalid configuration (frame " + std::to_string(frame) +
                  ", globals " + std::to_string(globals) + ")");
    c.frame = YawFrame(frame);
    c.globals = int(globals);
  }
  if (c.in < kFirstModelChannels || c.in > kCanonicalChannels)
    throw Error("model weights '" + path + "' expect " + std::to_string(c.in) + " input channels, the preprocessing has " +
                std::to_string(kFirstModelChannels) + " to " + std::to_string(kCanonicalChannels));
  c.floor = false;
  if (!first) {
    const uint32_t floor = r.u32();  // a reserved 0 before the floor
    if (floor > 1) throw Error("model weights '" + path + "' have an invalid configuration (floor " + std::to_string(floor) + ")");
    c.floor = floor == 1;
  } else {
    r.u32();  // reserved
  }
  DescriptorNet net(c);
  auto params = net->named_parameters();
  uint32_t count = r.u32();
  if (count != params.size())
    throw Error("model weights '" + path + "' hold " + std::to_string(count) + " tensors, the network has " +
                std::to_string(params.size()));
  torch::NoGradGuard no_grad;
  for (uint32_t i = 0; i < count; ++i) {
    uint32_t len = r.u32();
    r.need(len);
    std::string name = buf.substr(r.pos, len);
    r.pos += len;
    torch::Tensor* t = params.find(name);
    if (!t) throw Error("model weights '" + path + "' have an unknown tensor '" + name + "'");
    uint32_t n = r.u32();
    if (int64_t(n) != t->numel()) throw Error("model weights '" + path + "': tensor '" + name + "' has the wrong size");
    r.need(size_t(n) * 4);
    std::memcpy(t->data_ptr<float>(), buf.data() + r.pos, size_t(n) * 4);
    r.pos += size_t(n) * 4;
    if (!torch::isfinite(*t).all().item<bool>())
      throw Error("model weights '" + path + "': tensor '" + name + "' holds NaN or infinite values");
  }
  if (r.pos != buf.size()) throw Error("model weights '" + path + "' have trailing bytes");
  net->eval();
  return net;
}

}  // namespace lista::objfeat
