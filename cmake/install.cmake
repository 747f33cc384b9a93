# The installed package: `cmake --install build [--prefix P]`, then in a porter's project
#   find_package(legkit 0.2 REQUIRED COMPONENTS estimation)
#   target_link_libraries(app PRIVATE legkit::estimation)
# Components, each an interface target that links what it needs:
#   lie         legkit::lie         the Lie groups (lie/ is also its own package: find_package(lie))
#   model       legkit::model       robot models, URDF/MJCF robots through MuJoCo (needs MuJoCo)
#   io          legkit::io          the log format and the settings reader (needs yaml-cpp)
#   estimation  legkit::estimation  every estimator, the contact pipeline, the settings file, the
#                                   monitors, fusion (57.8, needs Ceres) and the estimator manager
# Headers install under include/legkit/ with the paths the kit uses (#include
# "estimation/state_estimator.hpp"). sim/, eval/ and tools/ are the kit's own and not installed.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(legkit_install_includedir ${CMAKE_INSTALL_INCLUDEDIR}/legkit)
set(legkit_package_dir ${CMAKE_INSTALL_LIBDIR}/cmake/legkit)

# legkit_package_component(<name> TARGETS <library>... )
# Exports the libraries as legkit::<library without "legkit_"> (legkit_model, legkit_io and
# legkit_estimation, which share their component's name, as legkit::<name>_core) and adds the
# component's interface target legkit::<name> linking all of them.
function(legkit_package_component name)
  cmake_parse_arguments(C "" "" "TARGETS" ${ARGN})
  foreach(target IN LISTS C_TARGETS)
    string(REGEX REPLACE "^legkit_" "" export_name ${target})
    if(export_name STREQUAL name)
      set(export_name ${name}_core)
    endif()
    set_target_properties(${target} PROPERTIES EXPORT_NAME ${export_name})
    target_include_directories(${target} INTERFACE $<INSTALL_INTERFACE:${legkit_install_includedir}>)
  endforeach()
  add_library(legkit_component_${name} INTERFACE)
  set_target_properties(legkit_component_${name} PROPERTIES EXPORT_NAME ${name})
  target_link_libraries(legkit_component_${name} INTERFACE ${C_TARGETS})
  install(TARGETS ${C_TARGETS} legkit_component_${name} EXPORT legkit_${name}_targets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(EXPORT legkit_${name}_targets NAMESPACE legkit:: FILE legkit-${name}-targets.cmake
          DESTINATION ${legkit_package_dir})
endfunction()

legkit_package_component(model TARGETS legkit_model legkit_mujoco legkit_mujoco_kinematics)
legkit_package_component(io TARGETS legkit_io legkit_yaml)
legkit_package_component(estimation TARGETS
  legkit_estimation legkit_imu legkit_allan legkit_leg_odometry legkit_linear_kf legkit_eskf
  legkit_invariant_ekf legkit_tsif legkit_contact legkit_contact_learned legkit_contact_factory
  legkit_slip legkit_contact_pipeline legkit_estimators legkit_settings legkit_monitors
  legkit_state_estimator legkit_fusion_extero legkit_fusion_delayed legkit_fusion_factors
  legkit_fusion_smoother)

foreach(folder model io estimation)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder} DESTINATION ${legkit_install_includedir}
          FILES_MATCHING PATTERN "*.hpp")
endforeach()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/legkitConfig.cmake.in
  ${PROJECT_BINARY_DIR}/legkitConfig.cmake INSTALL_DESTINATION ${legkit_package_dir})
# 0.x: a minor version may break the interface, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/legkitConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/legkitConfig.cmake
              ${PROJECT_BINARY_DIR}/legkitConfigVersion.cmake
        DESTINATION ${legkit_package_dir})
