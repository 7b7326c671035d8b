// SHA-256 (FIPS 180-4, §6.2), for the kernel cache's record of each compiled object: a
// corrupted, truncated or swapped file is told from the one eomc wrote before it is loaded.
// Small and dependency-free (eomc links no crypto library); checked against the FIPS 180-4
// example vectors in tests/cli/hardening_io.cpp.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace eomc {

class Sha256 {
public:
    Sha256();
    void update(const void* data, std::size_t size);
    void update(std::string_view bytes) { update(bytes.data(), bytes.size()); }
    std::array<std::uint8_t, 32> digest();  // once; the object is spent afterwards

private:
    void block(const std::uint8_t* p);

    std::array<std::uint32_t, 8> h_;
    std::array<std::uint8_t, 64> buffer_{};
    std::size_t buffered_ = 0;
    std::uint64_t length_ = 0;  // bytes
};

// Lower-case hex digest of `bytes`.
std::string sha256_hex(std::string_view bytes);

}  // namespace eomc
