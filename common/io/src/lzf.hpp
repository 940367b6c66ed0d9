// LZF (the compression of PCD binary_compressed): a byte-oriented LZ77 with
// literal runs of up to 32 bytes and back references of up to 8 KiB distance.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace lista::io::lzf {

// Appends the compressed form of in[0..n) to `out`.
void compress(const uint8_t* in, size_t n, std::vector<uint8_t>& out);

// Decompresses exactly into out[0..out_size); false if the stream is corrupt
// or does not produce exactly out_size bytes.
bool decompress(const uint8_t* in, size_t n, uint8_t* out, size_t out_size);

}  // namespace lista::io::lzf
