// A GLFW window with a Vulkan swapchain, for the sample game and the editor.
#pragma once

#include "speculum/framegraph.hpp"
#include "speculum/gpu/context.hpp"

#include <string>
#include <vector>

struct GLFWwindow;

namespace speculum::app {

// True when GLFW can open a window here (a display is reachable).
bool displayAvailable();

class Window {
public:
    // Throws Error(ExitCode::Failure) when no window can be opened.
    Window(const std::string& title, uint32_t width, uint32_t height);
    ~Window();
    Window(const Window&) = delete;
    Window& operator=(const Window&) = delete;
    GLFWwindow* handle() const { return window_; }
    bool shouldClose() const;
    void setTitle(const std::string& title);
    // Instance extensions the window system needs.
    static std::vector<const char*> requiredExtensions();

private:
    GLFWwindow* window_ = nullptr;
};

class Swapchain {
public:
    Swapchain(const gpu::Context& ctx, const Window& window);
    ~Swapchain();
    Swapchain(const Swapchain&) = delete;
    Swapchain& operator=(const Swapchain&) = delete;

    // Returns false when the swapchain had to be recreated (skip this frame).
    bool acquire();
    // Adds "game.present": blits `color` into the acquired image (scaled, with `filter`), leaves
    // it ready to present; returns the image's handle, for passes drawn over it (a HUD).
    TextureHandle addPresentPass(FrameGraph& graph, TextureHandle color, VkFilter filter = VK_FILTER_LINEAR);
    void present();
    VkSemaphore acquired() const { return acquired_[frame_]; }
    VkSemaphore rendered() const { return rendered_[image_]; }
    VkExtent2D extent() const { return extent_; }
    // For hosts that present with passes of their own (the editor draws its UI over the image).
    VkImage image() const { return images_[image_]; }
    VkFormat format() const { return format_; }
    uint32_t imageCount() const { return uint32_t(images_.size()); }
    VkImageUsageFlags usage() const { return usage_; }

private:
    void create();
    void destroy();
    const gpu::Context& ctx_;
    const Window& window_;
    VkSurfaceKHR surface_ = VK_NULL_HANDLE;
    VkSwapchainKHR swapchain_ = VK_NULL_HANDLE;
    VkFormat format_ = VK_FORMAT_B8G8R8A8_UNORM;
    VkExtent2D extent_{};
    VkImageUsageFlags usage_ = 0;
    std::vector<VkImage> images_;
    std::vector<VkSemaphore> acquired_;
    std::vector<VkSemaphore> rendered_;
    uint32_t image_ = 0;
    uint32_t frame_ = 0;
};

}  // namespace speculum::app
