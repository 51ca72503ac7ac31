#pragma once
/// \file A guard for third-party code that does not survive running out of memory.
#include <cstddef>
#include <memory>
#include <new>

namespace kerfab {

/// Memory kept free for a solver call [bytes]: CBC dereferences a null pointer when an allocation
/// fails inside its heuristics (found under `ulimit -v`), so it only starts with this much room.
inline constexpr std::size_t kSolverHeadroom = std::size_t{32} << 20;

/// Throws std::bad_alloc (reported as "out of memory") unless \p bytes can be allocated now.
inline void ensure_headroom(std::size_t bytes = kSolverHeadroom) {
  const std::unique_ptr<char[]> room(new (std::nothrow) char[bytes]);
  if (!room) throw std::bad_alloc();
}

}  // namespace kerfab
