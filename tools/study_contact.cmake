# `legkit study contact` and `legkit study slip` (sections 57.6 and 57.7): the contact detectors,
# the contact pipeline (with its slip guard) and the logistic model's training.
target_sources(legkit-study PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/legkit/study_contact.cpp)
target_link_libraries(legkit-study PRIVATE legkit_contact_pipeline legkit_contact_factory
                                           legkit_contact_training legkit_slip)
