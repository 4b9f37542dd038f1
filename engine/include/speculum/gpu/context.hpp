// The Vulkan host: instance, device choice, queue, validation, one-shot submits.
#pragma once

#include <vulkan/vulkan.h>

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace speculum::gpu {

// Owns one Vulkan handle; destroyed with the function given at construction (RAII for every
// Vulkan object without a class per type).
template <class T>
class Unique {
public:
    using Deleter = void (*)(VkDevice, T, const VkAllocationCallbacks*);
    Unique() = default;
    Unique(VkDevice device, T handle, Deleter deleter) : device_(device), handle_(handle), deleter_(deleter) {}
    Unique(Unique&& o) noexcept { *this = std::move(o); }
    Unique& operator=(Unique&& o) noexcept {
        if (this != &o) {
            reset();
            device_ = o.device_;
            handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
            deleter_ = o.deleter_;
        }
        return *this;
    }
    Unique(const Unique&) = delete;
    Unique& operator=(const Unique&) = delete;
    ~Unique() { reset(); }
    void reset() {
        if (handle_ != VK_NULL_HANDLE && deleter_) deleter_(device_, handle_, nullptr);
        handle_ = VK_NULL_HANDLE;
    }
    T get() const { return handle_; }
    operator T() const { return handle_; }  // NOLINT: handles are passed straight to vkCmd*
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
    VkDevice device_ = VK_NULL_HANDLE;
    T handle_ = VK_NULL_HANDLE;
    Deleter deleter_ = nullptr;
};

// Throws speculum::Error (ExitCode::Failure) with the call site when a Vulkan call fails.
void check(VkResult result, const char* what);

struct ContextOptions {
    std::string deviceName;         // --device: substring of the device name, case-insensitive
    bool validation = false;        // also forced on by SPECULUM_VALIDATION=1
    std::vector<const char*> instanceExtensions;  // e.g. from glfwGetRequiredInstanceExtensions
    bool swapchain = false;         // enable VK_KHR_swapchain on the device
};

class Context {
public:
    // Picks discrete, then integrated, then virtual, then CPU; logs the choice.
    // Throws Error(ExitCode::NoDevice) with what to install when there is no usable device.
    explicit Context(const ContextOptions& options = {});
    ~Context();
    Context(const Context&) = delete;
    Context& operator=(const Context&) = delete;

    VkInstance instance() const { return instance_; }
    VkPhysicalDevice physicalDevice() const { return physical_; }
    VkDevice device() const { return device_; }
    VkQueue queue() const { return queue_; }
    uint32_t queueFamily() const { return queueFamily_; }
    const VkPhysicalDeviceProperties& properties() const { return props_; }
    const std::string& deviceName() const { return name_; }
    double timestampPeriodNs() const { return props_.limits.timestampPeriod; }
    bool validationEnabled() const { return validation_; }
    // Validation messages (warnings and errors) seen since start; tests assert this stays 0.
    static int validationMessageCount();
    static const std::vector<std::string>& validationMessages();

    // Records with fn into a fresh command buffer, submits, waits.
    void submitAndWait(const std::function<void(VkCommandBuffer)>& fn) const;
    uint32_t findMemoryType(uint32_t typeBits, VkMemoryPropertyFlags flags) const;
    void setName(VkObjectType type, uint64_t handle, const std::string& name) const;

    PFN_vkCmdPushDescriptorSetKHR cmdPushDescriptorSet = nullptr;

private:
    void createInstance(const ContextOptions& options);
    void pickPhysicalDevice(const std::string& wanted);
    void createDevice(const ContextOptions& options);

    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    uint32_t queueFamily_ = 0;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkPhysicalDeviceProperties props_{};
    VkPhysicalDeviceMemoryProperties memProps_{};
    std::string name_;
    bool validation_ = false;
    bool debugUtils_ = false;
    PFN_vkSetDebugUtilsObjectNameEXT setObjectName_ = nullptr;
};

// Lists the devices Vulkan sees, as "name (type)" lines; for --device help and error messages.
std::vector<std::string> listDevices();

}  // namespace speculum::gpu
