# Sanitizer and fuzzing builds (see CMakePresets.json: asan, tsan, fuzz).
#
#   -DPLSLAM_SANITIZE=address,undefined   ASan + UBSan (gcc or clang)
#   -DPLSLAM_SANITIZE=thread              TSan
#   -DPLSLAM_FUZZ=ON                      libFuzzer targets in fuzz/ (clang only), with ASan + UBSan
#
# The flags go to every target of the tree (modules, tests, tools), so a finding in a
# module is caught whichever test reaches it. UBSan does not recover: the first finding
# aborts the process, so the test that reached it fails.
set(PLSLAM_SANITIZE "" CACHE STRING "Sanitizers for the whole tree: empty, address,undefined, or thread")
option(PLSLAM_FUZZ "Build the libFuzzer targets in fuzz/ (clang; implies ASan + UBSan)" OFF)

# Shared modules are linked with --no-undefined (cmake/PlslamModule.cmake). Clang leaves
# the sanitizer and fuzzer runtimes to the executable, so its sanitized modules have
# undefined runtime symbols by design: the check is off for those builds only.
set(PLSLAM_NO_UNDEFINED ON)

if(PLSLAM_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "PLSLAM_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang, or use the 'fuzz' preset")
  endif()
  if(PLSLAM_SANITIZE)
    message(FATAL_ERROR "PLSLAM_FUZZ brings its own sanitizers (address,undefined): leave PLSLAM_SANITIZE empty")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
  set(PLSLAM_NO_UNDEFINED OFF)
  message(STATUS "plslam: fuzzing build (libFuzzer + ASan + UBSan)")
elseif(PLSLAM_SANITIZE)
  if(PLSLAM_SANITIZE MATCHES "thread" AND PLSLAM_SANITIZE MATCHES "address")
    message(FATAL_ERROR "PLSLAM_SANITIZE: thread and address cannot be combined")
  endif()
  add_compile_options(-fsanitize=${PLSLAM_SANITIZE} -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${PLSLAM_SANITIZE})
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    set(PLSLAM_NO_UNDEFINED OFF)
  endif()
  message(STATUS "plslam: sanitizers ${PLSLAM_SANITIZE}")
endif()
