#include "speculum/core.hpp"
#include "speculum/gpu/context.hpp"
#include "speculum/gpu/resources.hpp"

#include <gtest/gtest.h>

#include <cstring>

using namespace speculum;

TEST(GpuContext, PicksADeviceAndUploadsAndReadsBack) {
    gpu::Context ctx;
    EXPECT_FALSE(ctx.deviceName().empty());
    gpu::ImageDesc desc{4, 3, VK_FORMAT_R32G32B32A32_SFLOAT, 1, 1, false,
                        VK_IMAGE_USAGE_SAMPLED_BIT | VK_IMAGE_USAGE_TRANSFER_DST_BIT |
                            VK_IMAGE_USAGE_TRANSFER_SRC_BIT};
    gpu::Image image(ctx, desc, "test.image");
    std::vector<float> pixels(4 * 3 * 4);
    for (size_t i = 0; i < pixels.size(); ++i) pixels[i] = float(i) * 0.25f - 3.0f;
    gpu::uploadImage(ctx, image, std::as_bytes(std::span(pixels)), false);
    std::vector<float> back =
        gpu::readImageRGBA(ctx, image.get(), desc, VK_IMAGE_LAYOUT_SHADER_READ_ONLY_OPTIMAL);
    EXPECT_EQ(back, pixels);
    EXPECT_EQ(gpu::Context::validationMessageCount(), 0);
}

TEST(GpuContext, UnknownDeviceNameIsExitFour) {
    try {
        gpu::Context ctx(gpu::ContextOptions{.deviceName = "no-such-device-xyz"});
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::NoDevice);
        EXPECT_NE(std::string(e.what()).find("no-such-device-xyz"), std::string::npos);
    }
}

TEST(GpuContext, AbsurdImageSizeIsRejectedWithName) {
    gpu::Context ctx;
    gpu::ImageDesc desc{100000, 4, VK_FORMAT_R8G8B8A8_UNORM};
    try {
        gpu::Image image(ctx, desc, "test.huge");
        FAIL() << "expected an error";
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ExitCode::BadArguments);
        EXPECT_NE(std::string(e.what()).find("test.huge"), std::string::npos);
    }
}
