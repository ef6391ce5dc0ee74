# Cross-compiling for Windows x64 with Debian's mingw-w64 (the posix thread model, whose libstdc++
# has std::thread and std::mutex, which OpenEXR's IlmThread needs).
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(CMAKE_C_COMPILER x86_64-w64-mingw32-gcc-posix)
set(CMAKE_CXX_COMPILER x86_64-w64-mingw32-g++-posix)
set(CMAKE_RC_COMPILER x86_64-w64-mingw32-windres)
# Libraries and headers come from the toolchain's root and the cross-built prefix (CMAKE_PREFIX_PATH,
# scripts/windows-deps.sh); programs (cmake's helpers, pkg-config) from the build machine.
set(CMAKE_FIND_ROOT_PATH /usr/x86_64-w64-mingw32 ${CMAKE_PREFIX_PATH})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
# Tests and try_run: the Windows executables run under Wine.
set(CMAKE_CROSSCOMPILING_EMULATOR wine)
