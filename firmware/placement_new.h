// Placement new, the only `new` this firmware uses (no heap): <new> on the host; avr-libc has
// no <new>, so the one declaration it needs is given here.
#pragma once

#if __has_include(<new>)
#include <new>
#else
inline void* operator new(decltype(sizeof(0)), void* where) noexcept { return where; }
#endif
