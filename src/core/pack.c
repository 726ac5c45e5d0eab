/* Compact frame-state formats (see hz/pack.h): the three-channel helpers; the per-value codecs are inline in
 * the header (the resolves and the tdense put call them for every pixel). */
#include "hz/pack.h"

void hz_half_pack3(uint16_t dst[3], const float src[3])
{
    dst[0] = hz_half_pack(src[0]);
    dst[1] = hz_half_pack(src[1]);
    dst[2] = hz_half_pack(src[2]);
}

void hz_half_unpack3(float dst[3], const uint16_t src[3])
{
    dst[0] = hz_half_unpack(src[0]);
    dst[1] = hz_half_unpack(src[1]);
    dst[2] = hz_half_unpack(src[2]);
}

