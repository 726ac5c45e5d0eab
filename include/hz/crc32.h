/*
 * hz/crc32.h — CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320), the checksum zlib, PNG and .hzb use.
 *
 * Contract: hz_crc32(0, data, n) is zlib's crc32(0, data, n); chaining works: hz_crc32(hz_crc32(0, a, na), b,
 * nb) equals the CRC of a followed by b. Integer-only, constant tables (8 KiB, no initialisation step), bit-exact on
 * every ISA and for any alignment of data. hz_crc32(0, "123456789", 9) == 0xCBF43926.
 */
#ifndef HZ_CRC32_H
#define HZ_CRC32_H

#include <stddef.h>
#include <stdint.h>

uint32_t hz_crc32(uint32_t crc, const void *data, size_t size);

#endif
