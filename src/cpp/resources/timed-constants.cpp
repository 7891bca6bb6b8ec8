// The timed layer (see src/control/timeline/): what an agenda item does,
// its status, the :when-busy policies and where an event comes from.
constexpr int kItemOp = 0, kItemDelta = 1, kItemValue = 2, kItemMacroStart = 3,
              kItemMacroEnd = 4, kItemFail = 5, kItemFinish = 6, kItemTimer = 7;
constexpr int kPending = 0, kDone = 1, kCancelled = 2;
constexpr int kQueue = 1, kOverride = 3, kInterleave = 4;
constexpr int kFromOutside = 0, kFromTimer = 1, kFromTrigger = 2;
constexpr long long kMaxItemsPerInstant = 100000;
