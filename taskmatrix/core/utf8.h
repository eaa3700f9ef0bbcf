// UTF-8 checks for text that comes from files (names, docs, parameters): where text is not
// UTF-8, and a copy with each bad byte replaced by U+FFFD for text that must be written anyway.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace taskmatrix::core {

// The offset of the first byte that does not begin a valid UTF-8 sequence (overlong forms,
// surrogates and values beyond U+10FFFF are invalid); nullopt if `text` is UTF-8.
std::optional<std::size_t> invalid_utf8_at(std::string_view text);

// `text` with every byte that does not begin a valid sequence replaced by U+FFFD.
std::string valid_utf8(std::string_view text);

}  // namespace taskmatrix::core
