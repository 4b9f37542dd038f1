// speculum-editor-save-loop: the editor's save routine in a loop, for the killed-mid-save test
// (kill_save_test.py). It opens SCENE as the editor does, then edits (moves its first probe, or
// adds one) and saves over SCENE through Document::save, forever, printing "saving N" before and
// "saved N" after each save. With --check it only loads SCENE and prints its node count (exit 3
// with the loader's message when it does not load).
#include "document.hpp"

#include "speculum/core.hpp"

#include <cstring>
#include <iostream>

using namespace speculum;

int main(int argc, char** argv) {
    if (argc != 3 || (std::strcmp(argv[1], "--check") != 0 && std::strcmp(argv[1], "--loop") != 0)) {
        std::cerr << "usage: speculum-editor-save-loop --check|--loop SCENE\n";
        return 2;
    }
    try {
        if (std::strcmp(argv[1], "--check") == 0) {
            Scene s = loadScene(argv[2]);
            std::cout << "nodes " << s.nodes.size() << "\n";
            return 0;
        }
        editor::Document doc = editor::Document::open(argv[2], {});
        for (int i = 0;; ++i) {
            doc.execute(
                editor::addProbe(doc, "probe.save" + std::to_string(i), {0.0f, 1.0f, float(i)}, ReflectionProbe{}));
            std::cout << "saving " << i << std::endl;
            doc.save();
            std::cout << "saved " << i << " nodes " << doc.scene().nodes.size() << std::endl;
        }
    } catch (const Error& e) {
        std::cerr << "speculum-editor-save-loop: " << e.what() << "\n";
        return int(e.code());
    }
}
