package dev.motionfusion.app.live

import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettings

/** How angles are shown. */
enum class AngleConvention {
    /**
     * Android's getOrientation: azimuth (0..360°, from magnetic north towards east, of the
     * screen's up direction), pitch (−90..90°, positive when the top edge tilts down), roll
     * (−180..180°, positive when the right edge tilts down: roll = atan2(−A_x, A_z) with A the
     * up direction in screen coordinates).
     */
    ANDROID,

    /**
     * Aerospace yaw, pitch, roll (intrinsic Z-Y-X) of the phone as a vehicle whose nose is the
     * screen's top edge, right wing the right edge, in North-East-Down: yaw 0..360° like azimuth,
     * pitch −90..90° positive nose up, roll −180..180° positive right edge down.
     */
    AEROSPACE,
}

/**
 * Everything the live screen's settings decide, validated: the user-editable part of the
 * filter settings ([beta], [zeta] in the units of [FilterSettings]; [mode] 6D/9D; rest bias
 * estimation; magnetic disturbance and accelerometer rejection), the angle convention and the
 * requested sensor rate. The rest of [FilterSettings] keeps its defaults.
 */
data class LiveSettings(
    val beta: Double = DEFAULT_FILTER.beta,
    val zeta: Double = DEFAULT_FILTER.zeta,
    val mode: FilterMode = DEFAULT_FILTER.mode,
    val restBiasEstimation: Boolean = DEFAULT_FILTER.restBiasEstimation,
    val magDisturbanceRejection: Boolean = DEFAULT_FILTER.magDisturbanceRejection,
    val accRejection: Boolean = DEFAULT_FILTER.accRejection,
    val convention: AngleConvention = AngleConvention.ANDROID,
    val rate: SamplingRate = SamplingRate.Hz(100),
) {
    init {
        require(beta.isFinite() && beta in 0.0..MAX_BETA) { "β must be 0..$MAX_BETA, got $beta" }
        require(zeta.isFinite() && zeta in 0.0..MAX_ZETA) { "ζ must be 0..$MAX_ZETA, got $zeta" }
    }

    /** The filter settings these stand for (fusion-core validates them too). */
    fun filterSettings(): FilterSettings = DEFAULT_FILTER.copy(
        beta = beta,
        zeta = zeta,
        mode = mode,
        restBiasEstimation = restBiasEstimation,
        magDisturbanceRejection = magDisturbanceRejection,
        accRejection = accRejection,
    )

    companion object {
        val DEFAULT_FILTER = FilterSettings()

        /** Upper bound for β, 1/s: far above any useful gain (β = 1 already follows the accelerometer within a second). */
        const val MAX_BETA = 5.0

        /** Upper bound for ζ, rad/s. */
        const val MAX_ZETA = 1.0
    }
}
