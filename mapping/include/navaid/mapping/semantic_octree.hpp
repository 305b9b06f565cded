#pragma once
// The semantic voxel map's tree: an OctoMap occupancy tree whose nodes also carry a class belief,
// in the pattern of OctoMap's ColorOcTree (node = OcTreeNode + payload, tree = OccupancyOcTreeBase
// over that node, registered with OctoMap's tree factory so that AbstractOcTree::read() makes it
// from a .ot file). The fusion rule is a template parameter (semantic_fusion.hpp).
//
// Include this header only where the tree itself is needed: it brings in OctoMap. Everything else
// talks to the map through semantic_map.hpp.
#include <istream>
#include <ostream>
#include <string>

#include <octomap/OcTreeNode.h>
#include <octomap/OccupancyOcTreeBase.h>

#include "navaid/mapping/semantic_fusion.hpp"

namespace navaid::mapping {

template <class Fusion>
class SemanticOcTree;

template <class Fusion>
class SemanticOcTreeNode : public octomap::OcTreeNode {
 public:
  friend class SemanticOcTree<Fusion>;  // the window pruning frees child arrays (as ColorOcTree)

  using State = typename Fusion::State;

  bool operator==(const SemanticOcTreeNode& rhs) const { return rhs.value == value && rhs.semantics_ == semantics_; }
  void copyData(const SemanticOcTreeNode& from) {
    OcTreeNode::copyData(from);
    semantics_ = from.semantics_;
  }
  const State& semantics() const { return semantics_; }
  State& semantics() { return semantics_; }
  SemanticBelief belief() const { return Fusion::belief(semantics_); }

  // Shadow OcTreeNode's (non-virtual) I/O, as ColorOcTreeNode does: OctoMap's tree reader calls
  // them on the concrete node type. Occupancy first, then the policy's state as raw bytes.
  std::istream& readData(std::istream& s) {
    OcTreeNode::readData(s);
    s.read(reinterpret_cast<char*>(&semantics_), sizeof(State));
    return s;
  }
  // Every byte of State is a member (no padding: semantic_fusion.hpp), so identical maps give
  // identical files.
  std::ostream& writeData(std::ostream& s) const {
    OcTreeNode::writeData(s);
    s.write(reinterpret_cast<const char*>(&semantics_), sizeof(State));
    return s;
  }

 private:
  State semantics_{};
};

template <class Fusion>
class SemanticOcTree : public octomap::OccupancyOcTreeBase<SemanticOcTreeNode<Fusion>> {
 public:
  using Node = SemanticOcTreeNode<Fusion>;

  explicit SemanticOcTree(double resolution_m);

  /// Virtual constructor for OctoMap's factory.
  SemanticOcTree* create() const override { return new SemanticOcTree(this->resolution); }
  /// "SemanticOcTree-max" / "SemanticOcTree-bayes": the id written into .ot files.
  std::string getTreeType() const override;

  typename Fusion::Params& fusion_params() { return params_; }
  const typename Fusion::Params& fusion_params() const { return params_; }

  /// Fuses one labelled point into the leaf `node` (a leaf returned by updateNode).
  void fuse(Node* node, const SemanticObservation& obs) const { Fusion::fuse(node->semantics(), obs, params_); }

  /// Occupancy of inner nodes (max of the children, OctoMap's rule) and their semantics (those of
  /// the most occupied child), after lazy updates.
  // Hides (OctoMap declares it non-virtual) the base version, which knows nothing of semantics.
  void updateInnerOccupancy();

  /// Deletes every node whose cube lies wholly outside the box [lo, hi] (and inner nodes left
  /// without children). OctoMap's deleteNode() cannot do this: it deletes a node whose child
  /// array is still allocated once its last child is gone, which OctoMap's own assertion rejects.
  void delete_outside(const octomap::point3d& lo, const octomap::point3d& hi);

 protected:
  void update_inner_recursive(Node* node, unsigned depth);
  /// True when `node` (cube centre c, half size h) is to be deleted by its parent.
  bool delete_outside_recursive(Node* node, const octomap::point3d& c, double h, const octomap::point3d& lo,
                                const octomap::point3d& hi);
  /// Frees child i of node with its whole subtree.
  void delete_child_subtree(Node* node, unsigned i);
  std::size_t subtree_size(const Node* node) const;

  // Registers the tree type with AbstractOcTree's factory once per program (ColorOcTree's idiom:
  // a static member whose constructor registers a prototype; ensure_linking() keeps it alive).
  class StaticMemberInitializer {
   public:
    StaticMemberInitializer();
    void ensure_linking() {}
  };
  static StaticMemberInitializer static_member_initializer_;

 private:
  typename Fusion::Params params_{};
};

extern template class SemanticOcTree<MaxFusion>;
extern template class SemanticOcTree<BayesianHistogramFusion>;

using MaxFusionOcTree = SemanticOcTree<MaxFusion>;
using BayesianOcTree = SemanticOcTree<BayesianHistogramFusion>;

}  // namespace navaid::mapping
