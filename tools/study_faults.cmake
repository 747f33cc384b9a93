# `legkit study faults` (section 57.9): the fault runs of chapter 57.9's troubleshooting table.
# Owner: monitors.
target_sources(legkit-study PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/legkit/study_faults.cpp)
target_link_libraries(legkit-study PRIVATE legkit_fault_injection legkit_contact_training)
