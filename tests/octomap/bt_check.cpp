// Reads a .bt file with the real OctoMap library and checks it against expected voxels.
// Usage: bt_check MAP.bt EXPECTED.txt   (EXPECTED: lines "x y z occupied(0|1)", voxel centres)
// Exit 0 when the library reads the file and every expected voxel has the expected state.
#include <octomap/OcTree.h>

#include <fstream>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: bt_check MAP.bt EXPECTED.txt\n";
    return 2;
  }
  octomap::OcTree tree(0.1);
  if (!tree.readBinary(argv[1])) {
    std::cerr << "octomap could not read " << argv[1] << "\n";
    return 1;
  }
  std::ifstream expected(argv[2]);
  double x, y, z;
  int occupied;
  size_t checked = 0, wrong = 0;
  while (expected >> x >> y >> z >> occupied) {
    octomap::OcTreeNode* node = tree.search(x, y, z);
    bool ok = node != nullptr && tree.isNodeOccupied(node) == (occupied == 1);
    if (!ok && wrong < 10) {
      std::cerr << "voxel at " << x << " " << y << " " << z << " expected " << occupied
                << (node ? (tree.isNodeOccupied(node) ? " got occupied" : " got free") : " got unknown")
                << "\n";
    }
    wrong += !ok;
    ++checked;
  }
  std::cout << "read " << argv[1] << ": res " << tree.getResolution() << ", " << tree.size()
            << " nodes, " << tree.getNumLeafNodes() << " leaves; " << checked << " voxels checked, "
            << wrong << " wrong\n";
  return (wrong == 0 && checked > 0) ? 0 : 1;
}
