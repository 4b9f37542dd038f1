// The document model without a window or a device: every command, undo and redo compared field
// by field against the scene before it, save and load, unknown content kept, autosave.
#include "../document.hpp"

#include "speculum/app/module.hpp"
#include "speculum/core.hpp"
#include "speculum/probes/probes.hpp"

#include <gtest/gtest.h>

#include <fstream>

namespace speculum::editor {
namespace {

std::filesystem::path gallery() {
    return std::filesystem::path(SPECULUM_SOURCE_DIR) / "assets/scenes/gallery.gltf";
}

std::filesystem::path tmpDir() {
    const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
    auto dir = std::filesystem::path(SPECULUM_TEST_TMP) / "editor" /
               (std::string(test->test_suite_name()) + "." + test->name());
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

std::vector<SettingDesc> table() {
    return app::settingsOf({}, {probes::moduleInfo()});
}

int materialNamed(const Scene& s, const std::string& name) {
    for (size_t i = 0; i < s.materials.size(); ++i)
        if (s.materials[i].name == name) return int(i);
    return -1;
}

int probeNode(const Scene& s) {
    for (size_t i = 0; i < s.nodes.size(); ++i)
        if (s.nodes[i].probe) return int(i);
    return -1;
}

void expectSame(const Scene& a, const Scene& b) {
    std::string why;
    EXPECT_TRUE(sameContent(a, b, &why)) << why;
}

TEST(EditorDocument, AddMoveResizeDeleteProbeAndUndoAll) {
    Document doc = Document::open(gallery(), table());
    const Scene original = doc.scene();
    EXPECT_FALSE(doc.dirty());

    ReflectionProbe p;
    p.extents = {2.0f, 1.5f, 2.0f};
    doc.execute(addProbe(doc, "probe.new", {1.0f, 1.5f, -2.0f}, p));
    int added = int(doc.scene().nodes.size() - 1);
    ASSERT_EQ(doc.scene().nodes.size(), original.nodes.size() + 1);
    EXPECT_TRUE(doc.dirty());
    EXPECT_EQ(doc.scene().nodes[added].probe->extents, p.extents);
    EXPECT_EQ(glm::vec3(doc.scene().nodes[added].world[3]), glm::vec3(1.0f, 1.5f, -2.0f));
    EXPECT_NE(std::find(doc.scene().roots.begin(), doc.scene().roots.end(), added), doc.scene().roots.end());
    // The probes module sees it where the document put it.
    EXPECT_EQ(glm::vec3(probes::describeProbe(doc.scene(), added).gpu.center), glm::vec3(1.0f, 1.5f, -2.0f));

    doc.execute(moveNode(doc, added, {3.0f, 1.0f, 0.5f}));
    EXPECT_EQ(doc.scene().nodes[added].translation, glm::vec3(3.0f, 1.0f, 0.5f));
    EXPECT_EQ(glm::vec3(doc.scene().nodes[added].world[3]), glm::vec3(3.0f, 1.0f, 0.5f));

    ReflectionProbe bigger = *doc.scene().nodes[added].probe;
    bigger.extents = {4.0f, 2.0f, 3.0f};
    bigger.blendDistance = 0.25f;
    doc.execute(setProbe(doc, added, bigger));
    EXPECT_EQ(*doc.scene().nodes[added].probe, bigger);
    const Scene beforeDelete = doc.scene();

    doc.execute(deleteProbe(doc, added));
    EXPECT_EQ(doc.scene().nodes.size(), original.nodes.size());  // an added node goes away entirely

    ASSERT_TRUE(doc.undo());
    expectSame(doc.scene(), beforeDelete);
    ASSERT_TRUE(doc.undo());
    ASSERT_TRUE(doc.undo());
    EXPECT_EQ(doc.scene().nodes[added].translation, glm::vec3(1.0f, 1.5f, -2.0f));
    EXPECT_EQ(glm::vec3(doc.scene().nodes[added].world[3]), glm::vec3(1.0f, 1.5f, -2.0f));
    ASSERT_TRUE(doc.undo());
    EXPECT_FALSE(doc.undo());
    expectSame(doc.scene(), original);
    EXPECT_FALSE(doc.dirty());

    // Redo all the way gives the deleted state again; undo once more the state before it.
    while (doc.redo()) {
    }
    EXPECT_EQ(doc.scene().nodes.size(), original.nodes.size());
    EXPECT_TRUE(doc.dirty());
    doc.undo();
    expectSame(doc.scene(), beforeDelete);
}

TEST(EditorDocument, DeletingAProbeTheFileHadKeepsTheNode) {
    Document doc = Document::open(gallery(), table());
    const Scene original = doc.scene();
    int node = probeNode(doc.scene());
    ASSERT_GE(node, 0) << "gallery.gltf has a probe";
    doc.execute(deleteProbe(doc, node));
    EXPECT_EQ(doc.scene().nodes.size(), original.nodes.size());
    EXPECT_FALSE(doc.scene().nodes[node].probe.has_value());
    doc.undo();
    expectSame(doc.scene(), original);
}

TEST(EditorDocument, MaterialEditsUndoRedoFieldByField) {
    Document doc = Document::open(gallery(), table());
    const Scene original = doc.scene();
    int chrome = materialNamed(doc.scene(), "chrome");
    ASSERT_GE(chrome, 0);
    Material m = doc.scene().materials[chrome];
    m.roughness = 0.35f;
    m.baseColor = {0.9f, 0.5f, 0.2f, 1.0f};
    doc.execute(setMaterial(doc, chrome, m));
    Material r = doc.scene().materials[chrome];
    MaterialReflections refl = reflectionsOf(r);
    refl.roughnessScale = 0.5f;
    refl.maxScreenSpaceRoughness = 0.3f;
    refl.mode = ReflectionMode::ProbesOnly;
    r.reflections = refl;
    doc.execute(setMaterial(doc, chrome, r));
    const Scene edited = doc.scene();
    EXPECT_EQ(doc.scene().materials[chrome].roughness, 0.35f);
    EXPECT_EQ(doc.scene().materials[chrome].reflections->mode, ReflectionMode::ProbesOnly);

    doc.undo();
    EXPECT_EQ(doc.scene().materials[chrome].reflections, original.materials[chrome].reflections);
    EXPECT_EQ(doc.scene().materials[chrome].roughness, 0.35f);
    doc.undo();
    expectSame(doc.scene(), original);
    EXPECT_FALSE(doc.dirty());
    doc.redo();
    doc.redo();
    expectSame(doc.scene(), edited);
    // A new edit after an undo drops the redo side.
    doc.undo();
    doc.execute(setSetting(doc, "probes.bounces", 3));
    EXPECT_FALSE(doc.canRedo());
    EXPECT_EQ(doc.settings().getInt("probes.bounces"), 3);
    doc.undo();
    EXPECT_EQ(doc.settings().getInt("probes.bounces"), int(doc.settings().find("probes.bounces")->defaultValue));
}

TEST(EditorDocument, SaveLoadCompareAndUnknownContentSurvives) {
    auto dir = tmpDir();
    // The gallery with content the engine does not model: an unknown extension on a node and
    // extras on a material, which an edit-save cycle must keep.
    Scene source = loadScene(gallery());
    nlohmann::json doc = source.document;
    doc["nodes"][0]["extensions"]["VENDOR_unknown"] = {{"answer", 42}};
    doc["materials"][0]["extras"] = {{"artist", "kept"}};
    std::filesystem::copy_file(gallery().parent_path() / "gallery.bin", dir / "gallery.bin");
    std::ofstream(dir / "in.gltf") << doc.dump(1);
    std::filesystem::create_directories(dir.parent_path() / "env");
    std::filesystem::copy_file(gallery().parent_path().parent_path() / "env/sunset.exr",
                               dir.parent_path() / "env/sunset.exr", std::filesystem::copy_options::overwrite_existing);
    // The sky is named relative to the scene: save-as into another folder must still find it.
    std::filesystem::create_directories(dir / "elsewhere");

    Document d = Document::open(dir / "in.gltf", table());
    int chrome = materialNamed(d.scene(), "chrome");
    Material m = d.scene().materials[chrome];
    m.roughness = 0.2f;
    m.reflections = reflectionsOf(m);
    m.reflections->roughnessOverride = 0.05f;
    d.execute(setMaterial(d, chrome, m));
    d.execute(addProbe(d, "probe.saved", {0.5f, 1.0f, 0.0f}, ReflectionProbe{}));
    d.execute(setSetting(d, "probes.bounces", 2));
    d.mutableSettings().set("probes.debug_view", 1.0);  // a debug view is never saved
    d.saveAs(dir / "out.gltf");
    EXPECT_FALSE(d.dirty());
    EXPECT_EQ(d.path(), dir / "out.gltf");

    Document back = Document::open(dir / "out.gltf", table());
    expectSame(back.scene(), d.scene());
    d.saveAs(dir / "elsewhere/moved.gltf");
    expectSame(loadScene(dir / "elsewhere/moved.gltf"), d.scene());
    EXPECT_EQ(std::filesystem::weakly_canonical(environmentPath(loadScene(dir / "elsewhere/moved.gltf"))),
              std::filesystem::weakly_canonical(dir.parent_path() / "env/sunset.exr"));
    d.saveAs(dir / "out.gltf");
    EXPECT_EQ(back.settings().getInt("probes.bounces"), 2);
    EXPECT_EQ(back.settings().getInt("probes.debug_view"), 0);
    EXPECT_EQ(back.scene().document["nodes"][0]["extensions"]["VENDOR_unknown"]["answer"], 42);
    EXPECT_EQ(back.scene().document["materials"][0]["extras"]["artist"], "kept");
    // Undoing past the save makes the document dirty again.
    d.undo();
    EXPECT_TRUE(d.dirty());
    d.redo();
    EXPECT_FALSE(d.dirty());
}

TEST(EditorDocument, SaveToAnUnwritablePlaceKeepsTheDocument) {
    Document d = Document::open(gallery(), table());
    d.execute(addProbe(d, "p", {0, 1, 0}, ReflectionProbe{}));
    try {
        d.saveAs("/proc/no/such/folder/scene.gltf");
        FAIL() << "saving under /proc must fail";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("/proc/no/such/folder/scene."), std::string::npos) << e.what();
    }
    EXPECT_TRUE(d.dirty());
    EXPECT_EQ(d.path(), gallery());
}

TEST(EditorDocument, AutosaveIsOfferedOnlyWhenNewerAndRecovers) {
    auto dir = tmpDir();
    Document d = Document::open(gallery(), table());
    d.saveAs(dir / "scene.gltf");
    EXPECT_FALSE(Document::newerAutosave(dir / "scene.gltf"));
    EXPECT_FALSE(d.autosave()) << "nothing to autosave in a clean document";
    d.execute(addProbe(d, "probe.autosaved", {0, 2, 0}, ReflectionProbe{}));
    ASSERT_TRUE(d.autosave());
    EXPECT_FALSE(d.autosave()) << "no new edit since the last autosave";
    auto side = Document::newerAutosave(dir / "scene.gltf");
    ASSERT_TRUE(side);
    EXPECT_EQ(*side, dir / "scene.autosave.glb");

    Document fresh = Document::open(dir / "scene.gltf", table());
    EXPECT_EQ(fresh.scene().nodes.size() + 1, d.scene().nodes.size());
    fresh.recoverFrom(*side);
    EXPECT_TRUE(fresh.dirty());
    EXPECT_EQ(fresh.path(), dir / "scene.gltf");
    expectSame(fresh.scene(), d.scene());
    fresh.save();
    EXPECT_FALSE(Document::newerAutosave(dir / "scene.gltf")) << "saving removes the stale autosave";
    expectSame(loadScene(dir / "scene.gltf"), d.scene());
}

}  // namespace
}  // namespace speculum::editor
