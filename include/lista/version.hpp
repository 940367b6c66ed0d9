// SDK version and build fingerprint: what a plugin must share with the core
// to be loaded. Bump LISTA_SDK_VERSION whenever a public header changes the
// layout of a type that crosses the plugin boundary.
#pragma once

#include <Eigen/Core>

#define LISTA_SDK_VERSION 6u

#define LISTA_STRINGIFY_IMPL(x) #x
#define LISTA_STRINGIFY(x) LISTA_STRINGIFY_IMPL(x)

// Everything that changes the binary layout of SDK types: compiler family and
// major version, libstdc++ string ABI, pointer size, Eigen version and Eigen's
// static alignment (Eigen types cross the boundary; -mavx/-march=native
// raises the alignment from 16 to 32 bytes and moves every member after a
// fixed-size Eigen matrix). A plugin built with a different fingerprint is
// refused with a message naming both.
#if defined(LISTA_FINGERPRINT_OVERRIDE)
#define LISTA_BUILD_FINGERPRINT LISTA_FINGERPRINT_OVERRIDE
#else
#if defined(__clang__)
#define LISTA_COMPILER_ID "clang" LISTA_STRINGIFY(__clang_major__)
#elif defined(__GNUC__)
#define LISTA_COMPILER_ID "gcc" LISTA_STRINGIFY(__GNUC__)
#else
#define LISTA_COMPILER_ID "unknown"
#endif
#if defined(_GLIBCXX_USE_CXX11_ABI)
#define LISTA_STRING_ABI "cxx11abi" LISTA_STRINGIFY(_GLIBCXX_USE_CXX11_ABI)
#else
#define LISTA_STRING_ABI "cxx11abi?"
#endif
#define LISTA_BUILD_FINGERPRINT                                            \
  LISTA_COMPILER_ID "/" LISTA_STRING_ABI "/ptr" LISTA_STRINGIFY(           \
      __SIZEOF_POINTER__) "/eigen" LISTA_STRINGIFY(EIGEN_WORLD_VERSION) "." \
      LISTA_STRINGIFY(EIGEN_MAJOR_VERSION) "." LISTA_STRINGIFY(EIGEN_MINOR_VERSION) "/align" \
      LISTA_STRINGIFY(EIGEN_MAX_STATIC_ALIGN_BYTES)
#endif
