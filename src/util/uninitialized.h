// A vector's allocator that leaves new elements of a trivial type uninitialized.
#pragma once

#include <memory>
#include <type_traits>
#include <utility>
#include <vector>

namespace emboss {

// std::allocator, except that resize() and the size constructor default-initialize the new
// elements instead of value-initializing them: a trivial type is left as the memory was. The pages
// of a large buffer are then not touched (faulted in) until they are written. For buffers whose
// contents are written before they are read (or read only where another array says they were).
template <class T>
struct UninitializedAllocator : std::allocator<T> {
  using std::allocator<T>::allocator;
  template <class U>
  struct rebind {
    using other = UninitializedAllocator<U>;
  };
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

template <class T>
using UninitializedVector = std::vector<T, UninitializedAllocator<T>>;

}  // namespace emboss
