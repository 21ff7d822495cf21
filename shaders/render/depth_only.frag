#version 430 core
// Depth-only passes (the shadow map's opaque casters): the rasteriser writes the depth.
void main()
{
}
