#include "navaid/mapping/semantic_octree.hpp"

namespace navaid::mapping {

template <class Fusion>
SemanticOcTree<Fusion>::SemanticOcTree(double resolution_m)
    : octomap::OccupancyOcTreeBase<Node>(resolution_m) {
  static_member_initializer_.ensure_linking();
}

template <class Fusion>
std::string SemanticOcTree<Fusion>::getTreeType() const {
  return "SemanticOcTree-" + std::string(Fusion::kName);
}

template <class Fusion>
void SemanticOcTree<Fusion>::updateInnerOccupancy() {
  if (this->root) update_inner_recursive(this->root, 0);
}

template <class Fusion>
void SemanticOcTree<Fusion>::update_inner_recursive(Node* node, unsigned depth) {
  if (!this->nodeHasChildren(node)) return;
  const Node* most_occupied = nullptr;
  for (unsigned i = 0; i < 8; ++i) {
    if (!this->nodeChildExists(node, i)) continue;
    Node* child = this->getNodeChild(node, i);
    if (depth + 1 < this->tree_depth) update_inner_recursive(child, depth + 1);
    if (most_occupied == nullptr || child->getLogOdds() > most_occupied->getLogOdds()) most_occupied = child;
  }
  node->setLogOdds(most_occupied->getLogOdds());
  node->semantics() = most_occupied->semantics();
}

template <class Fusion>
void SemanticOcTree<Fusion>::delete_outside(const octomap::point3d& lo, const octomap::point3d& hi) {
  if (this->root == nullptr) return;
  // The root cube spans [-r 2^(depth-1), r 2^(depth-1)] on each axis around the origin.
  const double half = this->resolution * static_cast<double>(1u << (this->tree_depth - 1));
  if (delete_outside_recursive(this->root, octomap::point3d(0, 0, 0), half, lo, hi)) this->clear();
}

template <class Fusion>
bool SemanticOcTree<Fusion>::delete_outside_recursive(Node* node, const octomap::point3d& c, double h,
                                                      const octomap::point3d& lo, const octomap::point3d& hi) {
  bool inside = true;
  for (unsigned a = 0; a < 3; ++a) {
    if (c(a) + h <= lo(a) || c(a) - h >= hi(a)) return true;  // wholly outside
    inside = inside && c(a) - h >= lo(a) && c(a) + h <= hi(a);
  }
  if (inside || !this->nodeHasChildren(node)) return false;  // a leaf across the border stays
  const double q = 0.5 * h;
  for (unsigned i = 0; i < 8; ++i) {
    if (!this->nodeChildExists(node, i)) continue;
    // OctoMap's child index: bit 0 = x, bit 1 = y, bit 2 = z, set for the upper half.
    const octomap::point3d child_c(static_cast<float>(c.x() + ((i & 1) ? q : -q)),
                                   static_cast<float>(c.y() + ((i & 2) ? q : -q)),
                                   static_cast<float>(c.z() + ((i & 4) ? q : -q)));
    if (delete_outside_recursive(this->getNodeChild(node, i), child_c, q, lo, hi)) delete_child_subtree(node, i);
  }
  if (this->nodeHasChildren(node)) return false;
  delete[] node->children;  // no child left: the node goes too (it is not the map of its cube)
  node->children = nullptr;
  return true;
}

template <class Fusion>
void SemanticOcTree<Fusion>::delete_child_subtree(Node* node, unsigned i) {
  Node* child = this->getNodeChild(node, i);
  this->tree_size -= subtree_size(child);
  this->size_changed = true;
  this->deleteNodeRecurs(child);
  node->children[i] = nullptr;
}

template <class Fusion>
std::size_t SemanticOcTree<Fusion>::subtree_size(const Node* node) const {
  std::size_t n = 1;
  if (!this->nodeHasChildren(node)) return n;
  for (unsigned i = 0; i < 8; ++i)
    if (this->nodeChildExists(node, i)) n += subtree_size(this->getNodeChild(node, i));
  return n;
}

template <class Fusion>
SemanticOcTree<Fusion>::StaticMemberInitializer::StaticMemberInitializer() {
  auto* prototype = new SemanticOcTree<Fusion>(0.1);
  prototype->clearKeyRays();
  octomap::AbstractOcTree::registerTreeType(prototype);
}

template <class Fusion>
typename SemanticOcTree<Fusion>::StaticMemberInitializer SemanticOcTree<Fusion>::static_member_initializer_;

template class SemanticOcTree<MaxFusion>;
template class SemanticOcTree<BayesianHistogramFusion>;

}  // namespace navaid::mapping
