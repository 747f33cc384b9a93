# `legkit study fusion` (section 57.8): proprioception alone against exteroceptive fusion on a long
# physics trot with simulated SLAM poses (loose coupling: extero; pose injection: delayed; the smoother). Owner:
# study.
target_sources(legkit PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/legkit/study_fusion.cpp)
target_link_libraries(legkit PRIVATE legkit_contact_pipeline legkit_contact_training legkit_fusion_extero
                                     legkit_fusion_delayed legkit_fusion_smoother)

# Its test runs the built program (--quick). tests/ is configured after tools/, so the test is
# registered once the top directory is done, when legkit_add_test exists; the packages tests/ found
# are found again here, as imported targets are local to the directory that found them.
function(legkit_study_fusion_test)
  find_package(Catch2 2.13 REQUIRED)
  find_package(rapidcheck REQUIRED)
  find_package(nlohmann_json 3 REQUIRED)
  legkit_add_test(test_study_fusion SOURCES ${PROJECT_SOURCE_DIR}/tests/tools/study_fusion_test.cpp
                  LIBS nlohmann_json::nlohmann_json LABELS "cli;fusion;57.8")
  target_compile_definitions(test_study_fusion PRIVATE LEGKIT_EXE="$<TARGET_FILE:legkit>")
  add_dependencies(test_study_fusion legkit)
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")  # as tests/CMakeLists.txt: ccache and the shared PCH
    target_compile_options(test_study_fusion PRIVATE -fpch-preprocess)
  endif()
endfunction()
cmake_language(DEFER DIRECTORY ${PROJECT_SOURCE_DIR} CALL legkit_study_fusion_test)
