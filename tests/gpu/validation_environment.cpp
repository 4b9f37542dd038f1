// Any Vulkan validation message fails the run it happened in, even in a test that forgot to
// check: ctest runs each discovered test on its own, so a failure here fails that test.
#include "speculum/gpu/context.hpp"

#include <gtest/gtest.h>

namespace {

class ValidationEnvironment : public ::testing::Environment {
public:
    void TearDown() override {
        const auto& messages = speculum::gpu::Context::validationMessages();
        EXPECT_EQ(speculum::gpu::Context::validationMessageCount(), 0)
            << "Vulkan validation reported: " << (messages.empty() ? "" : messages.front());
    }
};

[[maybe_unused]] ::testing::Environment* const kValidation =
    ::testing::AddGlobalTestEnvironment(new ValidationEnvironment);

}  // namespace
