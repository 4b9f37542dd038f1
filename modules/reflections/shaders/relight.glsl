// A surface's direct lighting seen from another direction (reflections.cmo_trace's CMO hits,
// reflections.resolve's mirror hits): what to add to its lit colour as seen from `vOld` for it
// to be seen from `vNew`. The diffuse parts cancel; the specular highlight moves with the viewer
// (a lamp's highlight on a chrome ball seen in a mirror is not where the camera sees it).
// `sun`: the visibility of the shadowed directional light at the surface (1 lit). Include after
// common/brdf.glsl, engine/lighting_common.glsl and engine/scene_lights.glsl.
#ifndef SPECULUM_REFLECTIONS_RELIGHT_GLSL
#define SPECULUM_REFLECTIONS_RELIGHT_GLSL

// The BRDF times cosine toward light direction l, seen from vNew less seen from vOld.
vec3 movedBRDFCos(vec3 n, vec3 vNew, vec3 vOld, vec3 l, vec3 baseColor, float metallic, float roughness) {
    return evalBRDFCos(n, vNew, l, baseColor, metallic, roughness) -
           evalBRDFCos(n, vOld, l, baseColor, metallic, roughness);
}

vec3 movedDirect(vec3 hp, vec3 n, vec3 vNew, vec3 vOld, vec3 baseColor, float metallic, float roughness, float sun) {
    vec3 delta = vec3(0.0);
    uint i = 0u;
    for (; i < kDirectionalLights; ++i) {
        GpuLight light = sceneLight(i);
        vec3 f = movedBRDFCos(n, vNew, vOld, -light.directionRange.xyz, baseColor, metallic, roughness);
        delta += f * light.radiance.rgb * (light.radiance.w > 0.0 ? sun : 1.0);
    }
    for (; i < kLights; ++i) {
        vec3 l;
        vec3 radiance = incidentRadiance(sceneLight(i), hp, l);
        delta += movedBRDFCos(n, vNew, vOld, l, baseColor, metallic, roughness) * radiance;
    }
    return delta;
}

#endif
