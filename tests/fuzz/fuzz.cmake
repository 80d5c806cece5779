# libFuzzer targets (clang only): one per tests/fuzz/fuzz_*.cpp, each linking the core alone.
file(GLOB EMBOSS_FUZZERS CONFIGURE_DEPENDS ${CMAKE_CURRENT_LIST_DIR}/fuzz_*.cpp)
foreach(src ${EMBOSS_FUZZERS})
  get_filename_component(name ${src} NAME_WE)
  add_executable(${name} ${src})
  target_link_libraries(${name} PRIVATE emboss_core)
  target_link_options(${name} PRIVATE -fsanitize=fuzzer)
endforeach()
