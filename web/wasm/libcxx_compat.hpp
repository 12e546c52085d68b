#pragma once
// Force-included into the codec sources of the WebAssembly build only: emscripten 3.1.6
// (Debian 12) ships LLVM 14's libc++, which lacks C++20's make_unique_for_overwrite.
// Same semantics: default-initialised (not zeroed) storage.
#include <memory>
#include <type_traits>

#if !defined(__cpp_lib_smart_ptr_for_overwrite)
namespace std {
template <class T>
requires(!is_array_v<T>) unique_ptr<T> make_unique_for_overwrite() { return unique_ptr<T>(new T); }
template <class T>
requires is_unbounded_array_v<T> unique_ptr<T> make_unique_for_overwrite(size_t n) {
    return unique_ptr<T>(new remove_extent_t<T>[n]);
}
}  // namespace std
#endif
