// A header that breaks every rule: the purity check must reject it (include.purity.self_test).
#include <vector>
static int counter = 0;
inline void* grab() {
  return new int(counter++);
}
inline void rebuild(int& slot) {
  ::new (static_cast<void*>(&slot)) int(*new int(1));  // placement, then the heap
}
