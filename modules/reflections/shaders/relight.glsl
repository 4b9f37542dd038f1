// A surface's direct lighting seen from another direction (reflections.cmo_trace's CMO hits,
// reflections.resolve's mirror hits): what to add to its lit colour as seen from `vOld` for it
// to be seen from `vNew`. The diffuse parts cancel; the specular highlight moves with the viewer
// (a lamp's highlight on a chrome ball seen in a mirror is not where the camera sees it).
// `sun`: the visibility of the shadowed directional light at the surface (1 lit). Include after
// common/brdf.glsl, engine/lighting_common.glsl and engine/scene_lights.glsl.
#ifndef SPECULUM_REFLECTIONS_RELIGHT_GLSL
#define SPECULUM_REFLECTIONS_RELIGHT_GLSL

// The specular lobe times cosine toward light direction l, seen from vNew less seen from vOld:
// the Lambert lobe is the same from both and cancels, so it is not evaluated (the two full
// BRDFs cost 12% of reflections.cmo_trace on gallery.main, MEASUREMENTS.md 2026-12-02).
vec3 movedSpecularCos(vec3 n, vec3 vNew, vec3 vOld, vec3 l, vec3 f0, float alpha) {
    float NoL = dot(n, l);
    if (NoL <= 0.0) return vec3(0.0);
    return (specularLobe(n, vNew, l, NoL, f0, alpha) - specularLobe(n, vOld, l, NoL, f0, alpha)) * NoL;
}

vec3 movedDirect(vec3 hp, vec3 n, vec3 vNew, vec3 vOld, vec3 baseColor, float metallic, float roughness, float sun) {
    vec3 delta = vec3(0.0);
    vec3 f0 = specularF0(baseColor, metallic);
    float alpha = roughnessToAlpha(roughness);
    uint i = 0u;
    for (; i < kDirectionalLights; ++i) {
        GpuLight light = sceneLight(i);
        vec3 f = movedSpecularCos(n, vNew, vOld, -light.directionRange.xyz, f0, alpha);
        delta += f * light.radiance.rgb * (light.radiance.w > 0.0 ? sun : 1.0);
    }
    for (; i < kLights; ++i) {
        vec3 l;
        vec3 radiance = incidentRadiance(sceneLight(i), hp, l);
        delta += movedSpecularCos(n, vNew, vOld, l, f0, alpha) * radiance;
    }
    return delta;
}

#endif
