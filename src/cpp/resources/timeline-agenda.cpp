bool Controller::later_(const Item& a, const Item& b) {
  return a.time > b.time || (a.time == b.time && a.seq > b.seq);
}

bool Controller::heap_order_(const std::shared_ptr<Item>& a, const std::shared_ptr<Item>& b) {
  return later_(*a, *b);
}

void Controller::push_item_(const std::shared_ptr<Item>& item) {
  agenda_.push_back(item);
  std::push_heap(agenda_.begin(), agenda_.end(), heap_order_);
}

void Controller::pop_item_() {
  std::pop_heap(agenda_.begin(), agenda_.end(), heap_order_);
  agenda_.pop_back();
}

// The earliest pending item, or null; cancelled items on top are dropped.
std::shared_ptr<Controller::Item> Controller::next_item_() {
  while (!agenda_.empty()) {
    if (agenda_.front()->status != kCancelled) return agenda_.front();
    pop_item_();
  }
  return nullptr;
}

