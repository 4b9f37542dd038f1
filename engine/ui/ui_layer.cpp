#include "speculum/ui/ui_layer.hpp"

#include "speculum/core.hpp"

#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_vulkan.h>
#include <imgui.h>

#include <algorithm>

namespace speculum::ui {

namespace {

void checkImgui(VkResult r) {
    if (r != VK_SUCCESS) gpu::check(r, "imgui vulkan backend");
}

}  // namespace

gpu::Unique<VkRenderPass> makeRenderPass(VkDevice dev, VkFormat format, VkAttachmentLoadOp load) {
    VkAttachmentDescription color{};
    color.format = format;
    color.samples = VK_SAMPLE_COUNT_1_BIT;
    color.loadOp = load;
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
    return gpu::Unique<VkRenderPass>(dev, rp, vkDestroyRenderPass);
}

gpu::Unique<VkFramebuffer> makeFramebuffer(VkDevice dev, VkRenderPass pass, VkImageView view, VkExtent2D e) {
    VkFramebufferCreateInfo fi{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
    fi.renderPass = pass;
    fi.attachmentCount = 1;
    fi.pAttachments = &view;
    fi.width = e.width;
    fi.height = e.height;
    fi.layers = 1;
    VkFramebuffer fb;
    gpu::check(vkCreateFramebuffer(dev, &fi, nullptr, &fb), "vkCreateFramebuffer");
    return gpu::Unique<VkFramebuffer>(dev, fb, vkDestroyFramebuffer);
}

void drawLists(VkCommandBuffer cmd, VkRenderPass pass, VkFramebuffer fb, VkRect2D area,
               const std::vector<ImDrawList*>& lists, const VkClearValue* clear,
               const std::function<void(VkCommandBuffer)>& before) {
    const ImDrawData* all = ImGui::GetDrawData();
    VkRenderPassBeginInfo bi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
    bi.renderPass = pass;
    bi.framebuffer = fb;
    bi.renderArea = area;
    bi.clearValueCount = clear ? 1 : 0;
    bi.pClearValues = clear;
    vkCmdBeginRenderPass(cmd, &bi, VK_SUBPASS_CONTENTS_INLINE);
    if (before) before(cmd);
    if (all && !lists.empty()) {
        ImDrawData part = *all;
        part.CmdLists = const_cast<ImDrawList**>(lists.data());
        part.CmdListsCount = int(lists.size());
        part.TotalVtxCount = part.TotalIdxCount = 0;
        for (const ImDrawList* l : lists) {
            part.TotalVtxCount += l->VtxBuffer.Size;
            part.TotalIdxCount += l->IdxBuffer.Size;
        }
        ImGui_ImplVulkan_RenderDrawData(&part, cmd);
    }
    vkCmdEndRenderPass(cmd);
}

std::vector<ImDrawList*> allLists() {
    std::vector<ImDrawList*> all;
    if (const ImDrawData* draw = ImGui::GetDrawData()) all.assign(draw->CmdLists, draw->CmdLists + draw->CmdListsCount);
    return all;
}

UiLayer::UiLayer(const gpu::Context& ctx, GLFWwindow* window, VkFormat format, uint32_t imageCount)
    : ctx_(ctx), format_(format) {
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
    renderPass_ = makeRenderPass(dev, format, VK_ATTACHMENT_LOAD_OP_LOAD);

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    ImGui::GetIO().IniFilename = nullptr;  // the layout is the host's, not a file's
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

VkFramebuffer UiLayer::frameFramebuffer(VkImageView view, VkExtent2D e) {
    framebuffers_.push_back(makeFramebuffer(ctx_.device(), renderPass_, view, e));
    return framebuffers_.back();
}

TextureHandle UiLayer::addPass(FrameGraph& graph, TextureHandle target, const std::string& name) {
    struct Data {
        TextureHandle target;
    };
    const Data& d = graph.addPass<Data>(
        name, PassType::Raster,
        [&](PassBuilder& b, Data& data) {
            data.target = b.write(target, TextureUsage::ColorAttachment);
            b.sideEffect();
        },
        [this](const Data& data, PassContext& pc) {
            VkExtent2D e = pc.extent(data.target);
            drawLists(pc.cmd(), renderPass_, frameFramebuffer(pc.view(data.target), e), {{0, 0}, e}, allLists(), nullptr);
        });
    return d.target;
}

void UiLayer::endFrame() {
    framebuffers_.clear();
}

}  // namespace speculum::ui
