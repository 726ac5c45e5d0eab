/*
 * hz/hz.h — the public entry point of the hzrt core library (libhz.a): include this one header.
 *
 * Contract: the core is freestanding C99. It allocates only from arenas the caller hands it (hz/arena.h),
 * reports failures as hz_status_t with messages (hz/status.h), and touches no OS or library API; ports
 * (port/<os>/) supply files, threads, clocks and devices.
 */
#ifndef HZ_HZ_H
#define HZ_HZ_H

#define HZ_VERSION_MAJOR 0
#define HZ_VERSION_MINOR 1
#define HZ_VERSION_PATCH 0
#define HZ_VERSION_STRING "0.1.0"

#include "hz/arena.h"
#include "hz/base.h"
#include "hz/config.h"
#include "hz/fixed.h"
#include "hz/fmt.h"
#include "hz/hash.h"
#include "hz/status.h"
#include "hz/vmath.h"

#endif /* HZ_HZ_H */
