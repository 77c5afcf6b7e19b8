# ASan + UBSan for the `debug` preset, TSan for the concurrency tests' preset.
if(HANDSCAN_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
if(HANDSCAN_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()
# libFuzzer targets (tools/fuzz): every library is built with coverage instrumentation and
# ASan + UBSan; only the fuzz_* executables link the libFuzzer driver (handscan_fuzz_target).
if(HANDSCAN_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "HANDSCAN_FUZZ needs clang (libFuzzer): configure with CC=clang CXX=clang++, "
                        "or run tools/fuzz")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-omit-frame-pointer
                      -fno-sanitize-recover=undefined -Wno-unknown-warning-option)
  add_link_options(-fsanitize=address,undefined)
endif()
