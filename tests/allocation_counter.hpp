// Counts every heap allocation a test program makes, by replacing the global operator new and
// delete: a test reads allocationCount() before and after the calls it checks.
//
// ONE translation unit per program: this header DEFINES the replacement operators (a replacement
// operator new or delete may not be inline, so it must be defined exactly once in a program).
// Include it from exactly one .cpp of a test program (its test file), never from another header,
// or the program breaks the one-definition rule (duplicate symbols at link time).
#pragma once

#include <atomic>
#include <cstdlib>
#include <new>

namespace legkit::test {

namespace detail {
inline std::atomic<long> allocations{0};  // incremented by every form of operator new below
}

// Heap allocations made so far by this program.
inline long allocationCount() {
  return detail::allocations.load();
}

}  // namespace legkit::test

void* operator new(std::size_t size) {
  ++legkit::test::detail::allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) {
  return operator new(size);
}
// The nothrow forms too (Catch uses them): every form must pair with the free() below, or a
// sanitizer build reports an allocation/deallocation mismatch.
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  ++legkit::test::detail::allocations;
  return std::malloc(size == 0 ? 1 : size);
}
void* operator new[](std::size_t size, const std::nothrow_t& tag) noexcept {
  return operator new(size, tag);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
