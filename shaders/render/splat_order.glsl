// A float's code as an unsigned integer that orders as the float does (negative values
// too), for atomicMin on the bits; and back. splat.comp and splat_resolve.comp share it.
uint splat_order(float f)
{
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : b | 0x80000000u;
}

float splat_value(uint u)
{
    return uintBitsToFloat((u & 0x80000000u) != 0u ? u & 0x7fffffffu : ~u);
}
