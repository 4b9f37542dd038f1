#include "speculum/app/window.hpp"

#include "speculum/core.hpp"

#define GLFW_INCLUDE_VULKAN
#include <GLFW/glfw3.h>

#include <algorithm>
#include <cstdlib>

namespace speculum::app {
namespace {

struct GlfwLibrary {
    bool ok = false;
    GlfwLibrary() {
        glfwSetErrorCallback([](int, const char*) {});  // failures are reported by our own messages
        ok = glfwInit() == GLFW_TRUE;
    }
    ~GlfwLibrary() {
        if (ok) glfwTerminate();
    }
};

GlfwLibrary& glfw() {
    static GlfwLibrary lib;
    return lib;
}

}  // namespace

bool displayAvailable() {
    // Checking the variables first avoids GLFW's slow connection attempts on servers.
    const char* x11 = std::getenv("DISPLAY");
    const char* wayland = std::getenv("WAYLAND_DISPLAY");
    if ((!x11 || !*x11) && (!wayland || !*wayland)) return false;
    return glfw().ok;
}

Window::Window(const std::string& title, uint32_t width, uint32_t height) {
    if (!displayAvailable()) throw Error(ExitCode::Failure, "no display");
    glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
    window_ = glfwCreateWindow(int(width), int(height), title.c_str(), nullptr, nullptr);
    if (!window_) throw Error(ExitCode::Failure, "cannot open a window");
}

Window::~Window() {
    if (window_) glfwDestroyWindow(window_);
}

bool Window::shouldClose() const { return glfwWindowShouldClose(window_); }
void Window::setTitle(const std::string& title) { glfwSetWindowTitle(window_, title.c_str()); }

std::vector<const char*> Window::requiredExtensions() {
    uint32_t n = 0;
    const char** names = glfw().ok ? glfwGetRequiredInstanceExtensions(&n) : nullptr;
    return names ? std::vector<const char*>(names, names + n) : std::vector<const char*>{};
}

Swapchain::Swapchain(const gpu::Context& ctx, const Window& window) : ctx_(ctx), window_(window) {
    gpu::check(glfwCreateWindowSurface(ctx.instance(), window.handle(), nullptr, &surface_), "glfwCreateWindowSurface");
    VkBool32 supported = VK_FALSE;
    vkGetPhysicalDeviceSurfaceSupportKHR(ctx.physicalDevice(), ctx.queueFamily(), surface_, &supported);
    if (!supported) throw Error(ExitCode::NoDevice, ctx.deviceName() + " cannot present to this window");
    create();
}

Swapchain::~Swapchain() {
    vkDeviceWaitIdle(ctx_.device());
    destroy();
    vkDestroySurfaceKHR(ctx_.instance(), surface_, nullptr);
}

void Swapchain::create() {
    VkSurfaceCapabilitiesKHR caps;
    vkGetPhysicalDeviceSurfaceCapabilitiesKHR(ctx_.physicalDevice(), surface_, &caps);
    int fw = 0, fh = 0;
    glfwGetFramebufferSize(window_.handle(), &fw, &fh);
    extent_ = caps.currentExtent.width != UINT32_MAX ? caps.currentExtent : VkExtent2D{uint32_t(fw), uint32_t(fh)};
    extent_.width = std::max(1u, extent_.width);
    extent_.height = std::max(1u, extent_.height);
    uint32_t n = 0;
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx_.physicalDevice(), surface_, &n, nullptr);
    std::vector<VkSurfaceFormatKHR> formats(n);
    vkGetPhysicalDeviceSurfaceFormatsKHR(ctx_.physicalDevice(), surface_, &n, formats.data());
    // The tonemapper writes sRGB-encoded values, so the swapchain must be UNORM (no second encode).
    format_ = formats.empty() ? VK_FORMAT_B8G8R8A8_UNORM : formats[0].format;
    VkColorSpaceKHR space = formats.empty() ? VK_COLOR_SPACE_SRGB_NONLINEAR_KHR : formats[0].colorSpace;
    for (auto& f : formats)
        if (f.format == VK_FORMAT_B8G8R8A8_UNORM || f.format == VK_FORMAT_R8G8B8A8_UNORM) {
            format_ = f.format;
            space = f.colorSpace;
            break;
        }
    VkSwapchainCreateInfoKHR info{VK_STRUCTURE_TYPE_SWAPCHAIN_CREATE_INFO_KHR};
    info.surface = surface_;
    info.minImageCount = std::max(caps.minImageCount, 2u);
    if (caps.maxImageCount) info.minImageCount = std::min(info.minImageCount, caps.maxImageCount);
    info.imageFormat = format_;
    info.imageColorSpace = space;
    info.imageExtent = extent_;
    info.imageArrayLayers = 1;
    // Transfer source where the surface allows it: the editor reads the window back for pictures.
    usage_ = VK_IMAGE_USAGE_TRANSFER_DST_BIT | VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT |
             (caps.supportedUsageFlags & VK_IMAGE_USAGE_TRANSFER_SRC_BIT);
    info.imageUsage = usage_;
    info.imageSharingMode = VK_SHARING_MODE_EXCLUSIVE;
    info.preTransform = caps.currentTransform;
    info.compositeAlpha = VK_COMPOSITE_ALPHA_OPAQUE_BIT_KHR;
    info.presentMode = VK_PRESENT_MODE_FIFO_KHR;
    info.clipped = VK_TRUE;
    gpu::check(vkCreateSwapchainKHR(ctx_.device(), &info, nullptr, &swapchain_), "vkCreateSwapchainKHR");
    vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &n, nullptr);
    images_.resize(n);
    vkGetSwapchainImagesKHR(ctx_.device(), swapchain_, &n, images_.data());
    VkSemaphoreCreateInfo s{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
    acquired_.resize(n);
    rendered_.resize(n);
    for (uint32_t i = 0; i < n; ++i) {
        gpu::check(vkCreateSemaphore(ctx_.device(), &s, nullptr, &acquired_[i]), "vkCreateSemaphore");
        gpu::check(vkCreateSemaphore(ctx_.device(), &s, nullptr, &rendered_[i]), "vkCreateSemaphore");
    }
}

void Swapchain::destroy() {
    for (VkSemaphore s : acquired_) vkDestroySemaphore(ctx_.device(), s, nullptr);
    for (VkSemaphore s : rendered_) vkDestroySemaphore(ctx_.device(), s, nullptr);
    acquired_.clear();
    rendered_.clear();
    if (swapchain_) vkDestroySwapchainKHR(ctx_.device(), swapchain_, nullptr);
    swapchain_ = VK_NULL_HANDLE;
}

bool Swapchain::acquire() {
    frame_ = (frame_ + 1) % uint32_t(acquired_.size());
    VkResult r = vkAcquireNextImageKHR(ctx_.device(), swapchain_, UINT64_MAX, acquired_[frame_], VK_NULL_HANDLE, &image_);
    if (r == VK_ERROR_OUT_OF_DATE_KHR) {
        vkDeviceWaitIdle(ctx_.device());
        destroy();
        create();
        return false;
    }
    if (r != VK_SUBOPTIMAL_KHR) gpu::check(r, "vkAcquireNextImageKHR");
    return true;
}

TextureHandle Swapchain::addPresentPass(FrameGraph& graph, TextureHandle color, VkFilter filter) {
    TextureDesc desc{.width = extent_.width, .height = extent_.height, .format = format_};
    TextureHandle target = graph.importTexture(
        "game.swapchain", desc,
        {images_[image_], VK_IMAGE_LAYOUT_UNDEFINED, VK_IMAGE_LAYOUT_PRESENT_SRC_KHR, usage_});
    struct Data {
        TextureHandle src, dst;
    };
    return graph.addPass<Data>(
        "game.present", PassType::Transfer,
        [&](PassBuilder& b, Data& d) {
            d.src = b.read(color, TextureUsage::TransferSrc);
            d.dst = b.write(target, TextureUsage::TransferDst);
            b.sideEffect();
        },
        [filter](const Data& d, PassContext& pc) {
            VkExtent2D s = pc.extent(d.src), t = pc.extent(d.dst);
            VkImageBlit blit{};
            blit.srcSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            blit.srcOffsets[1] = {int32_t(s.width), int32_t(s.height), 1};
            blit.dstSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
            blit.dstOffsets[1] = {int32_t(t.width), int32_t(t.height), 1};
            vkCmdBlitImage(pc.cmd(), pc.image(d.src), VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, pc.image(d.dst),
                           VK_IMAGE_LAYOUT_TRANSFER_DST_OPTIMAL, 1, &blit, filter);
        })
        .dst;
}

void Swapchain::present() {
    VkPresentInfoKHR info{VK_STRUCTURE_TYPE_PRESENT_INFO_KHR};
    info.waitSemaphoreCount = 1;
    info.pWaitSemaphores = &rendered_[image_];
    info.swapchainCount = 1;
    info.pSwapchains = &swapchain_;
    info.pImageIndices = &image_;
    VkResult r = vkQueuePresentKHR(ctx_.queue(), &info);
    if (r == VK_ERROR_OUT_OF_DATE_KHR || r == VK_SUBOPTIMAL_KHR) {
        vkDeviceWaitIdle(ctx_.device());
        destroy();
        create();
        return;
    }
    gpu::check(r, "vkQueuePresentKHR");
}

}  // namespace speculum::app
