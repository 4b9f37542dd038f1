#include "ui_layer.hpp"

#include "speculum/core.hpp"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

namespace speculum::editor {

namespace {

void checkImgui(VkResult r) {
    if (r != VK_SUCCESS) gpu::check(r, "imgui vulkan backend");
}

}  // namespace

UiLayer::UiLayer(const gpu::Context& ctx, GLFWwindow* window, VkFormat format, uint32_t imageCount) : ctx_(ctx) {
    VkDevice dev = ctx.device();
    VkDescriptorPoolSize size{VK_DESCRIPTOR_TYPE_COMBINED_IMAGE_SAMPLER, 16};
    VkDescriptorPoolCreateInfo pi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
    pi.flags = VK_DESCRIPTOR_POOL_CREATE_FREE_DESCRIPTOR_SET_BIT;
    pi.maxSets = 16;
    pi.poolSizeCount = 1;
    pi.pPoolSizes = &size;
    VkDescriptorPool pool;
    gpu::check(vkCreateDescriptorPool(dev, &pi, nullptr, &pool), "vkCreateDescriptorPool");
    pool_ = gpu::Unique<VkDescriptorPool>(dev, pool, vkDestroyDescriptorPool);

    // The frame graph puts the image in COLOR_ATTACHMENT_OPTIMAL before the pass and moves it
    // to PRESENT_SRC after: the render pass loads, draws and leaves the layout alone.
    VkAttachmentDescription color{};
    color.format = format;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = VK_ATTACHMENT_LOAD_OP_LOAD;
    color.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    color.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    color.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    color.initialLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    color.finalLayout = VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL;
    VkAttachmentReference ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
    VkSubpassDescription sub{};
    sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
    sub.colorAttachmentCount = 1;
    sub.pColorAttachments = &ref;
    VkRenderPassCreateInfo ri{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
    ri.attachmentCount = 1;
    ri.pAttachments = &color;
    ri.subpassCount = 1;
    ri.pSubpasses = &sub;
    VkRenderPass rp;
    gpu::check(vkCreateRenderPass(dev, &ri, nullptr, &rp), "vkCreateRenderPass");
    renderPass_ = gpu::Unique<VkRenderPass>(dev, rp, vkDestroyRenderPass);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is the editor's, not a file's
    ImGui::StyleColorsDark();
    glfwInit_ = ImGui_ImplGlfw_InitForVulkan(window, true);
    if (!glfwInit_) throw Error(ExitCode::Failure, "ImGui's GLFW backend failed to start");
    ImGui_ImplVulkan_InitInfo info{};
    info.Instance = ctx.instance();
    info.PhysicalDevice = ctx.physicalDevice();
    info.Device = dev;
    info.QueueFamily = ctx.queueFamily();
    info.Queue = ctx.queue();
    info.DescriptorPool = pool_;
    info.MinImageCount = std::max(2u, imageCount);
    info.ImageCount = std::max(2u, imageCount);
    info.MSAASamples = VK_SAMPLE_COUNT_1_BIT;
    info.CheckVkResultFn = checkImgui;
    vulkanInit_ = ImGui_ImplVulkan_Init(&info, renderPass_);
    if (!vulkanInit_) throw Error(ExitCode::Failure, "ImGui's Vulkan backend failed to start");
    ctx.submitAndWait([](VkCommandBuffer cmd) { ImGui_ImplVulkan_CreateFontsTexture(cmd); });
    ImGui_ImplVulkan_DestroyFontUploadObjects();
}

UiLayer::~UiLayer() {
    vkDeviceWaitIdle(ctx_.device());
    framebuffers_.clear();
    if (vulkanInit_) ImGui_ImplVulkan_Shutdown();
    if (glfwInit_) ImGui_ImplGlfw_Shutdown();
    ImGui::DestroyContext();
}

void UiLayer::beginInput() {
    ImGui_ImplVulkan_NewFrame();
    ImGui_ImplGlfw_NewFrame();
}

TextureHandle UiLayer::addPass(FrameGraph& graph, TextureHandle target) {
    struct Data {
        TextureHandle target;
    };
    const Data& d = graph.addPass<Data>(
        "editor.ui", PassType::Raster,
        [&](PassBuilder& b, Data& data) {
            data.target = b.write(target, TextureUsage::ColorAttachment);
            b.sideEffect();
        },
        [this](const Data& data, PassContext& pc) {
            VkExtent2D e = pc.extent(data.target);
            VkImageView view = pc.view(data.target);
            VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
            fi.renderPass = renderPass_;
            fi.attachmentCount = 1;
            fi.pAttachments = &view;
            fi.width = e.width;
            fi.height = e.height;
            fi.layers = 1;
            VkFramebuffer fb;
            gpu::check(vkCreateFramebuffer(ctx_.device(), &fi, nullptr, &fb), "vkCreateFramebuffer");
            framebuffers_.emplace_back(ctx_.device(), fb, vkDestroyFramebuffer);
            VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
            bi.renderPass = renderPass_;
            bi.framebuffer = fb;
            bi.renderArea = {{0, 0}, e};
            vkCmdBeginRenderPass(pc.cmd(), &bi, VK_SUBPASS_CONTENTS_INLINE);
            if (ImDrawData* draw = ImGui::GetDrawData()) ImGui_ImplVulkan_RenderDrawData(draw, pc.cmd());
            vkCmdEndRenderPass(pc.cmd());
        });
    return d.target;
}

void UiLayer::endFrame() {
    framebuffers_.clear();
}

}  // namespace speculum::editor
