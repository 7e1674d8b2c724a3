// A rod's contact view (Rod::contact_view_of): what a rod-contact field (positions, radii, arc
// lengths, depth past the entry, contact stiffness) and a coil sleep (positions, first node,
// tolerance) read of a rod, copied so that another thread may solve the rod meanwhile; and its
// published view, which adds what the readers of its results take (Simulator::released_view).
#include "tool/rod.hpp"

namespace cathbox::tool {

Rod Rod::contact_view_of(const Rod& rod) {
  Rod view;
  view.spec_ = rod.spec_;
  view.mirror_contact_view(rod);
  return view;
}

void Rod::mirror_contact_view(const Rod& rod) {
  settings_ = rod.settings_;
  length_mm_ = rod.length_mm_;
  insertion_mm_ = rod.insertion_mm_;
  first_ = rod.first_;
  first_free_ = rod.first_free_;
  free_ = rod.free_;
  x_.assign(rod.x_.begin(), rod.x_.end());
  radius_.assign(rod.radius_.begin(), rod.radius_.end());
  from_tip_.assign(rod.from_tip_.begin(), rod.from_tip_.end());
}

void Rod::mirror_published_view(const Rod& rod) {
  mirror_contact_view(rod);
  t_.assign(rod.t_.begin(), rod.t_.end());
  m1_.assign(rod.m1_.begin(), rod.m1_.end());
  contacts_.assign(rod.contacts_.begin(), rod.contacts_.end());
  warm_ok_ = rod.warm_ok_;
}

}  // namespace cathbox::tool
