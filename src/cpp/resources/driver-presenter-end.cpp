
private:
  // A macro line waiting for its end: where it is, whose, and from when.
  struct OpenMacro { std::size_t line; const ctl::Op* op; ctl::Time start; };
  std::vector<std::string> lines_;
  std::vector<OpenMacro> open_;
  std::size_t flushed_ = 0;

  static std::string op_text(const ctl::Op& op, ctl::Time start, ctl::Time end) {
    std::string kind = op.kind;
    std::string middle = kind == "director" ? std::string(" :director ") + op.script
                       : kind == "code" ? std::string(" :code t")
                       : std::string(" :script ") + op.script;
    return std::string("(:op ") + op.name + middle + " :start " + number(start) + " :end " + number(end) + ")";
  }
  void line_op(const ctl::Op& op, ctl::Time start, ctl::Time end) { add(op_text(op, start, end)); }
  void add(const std::string& line) { lines_.push_back(line); flush(); }
  void flush() {
    if (!open_.empty()) return;
    for (; flushed_ < lines_.size(); ++flushed_) print_line(lines_[flushed_]);
  }
};

}  // namespace


