/*
 * Settings of the Madgwick filter (package dev.motionfusion.core.filter).
 *
 * Frames: sensor readings in the Android device frame (x right, y up along the screen, z out of
 * the screen); the filter works internally in the report's North-West-Up earth frame and outputs
 * in a [WorldFrame]. Units: SI (rad/s, m/s², µT, s); angles in radians.
 */
package dev.motionfusion.core.filter

import dev.motionfusion.core.WorldFrame
import kotlin.math.PI

/** Which sensors the filter fuses. */
public enum class FilterMode {
    /** 6D: gyroscope + accelerometer (the report's IMU update). Heading drifts. */
    IMU,

    /** 9D: gyroscope + accelerometer + magnetometer (the report's MARG update). */
    MARG,
}

/** How the filter starts. */
public enum class Initialisation {
    /** The report's choice: start at the identity and converge at the rate β. */
    IDENTITY,

    /**
     * From the first valid accelerometer sample (inclination) and, in [FilterMode.MARG], the
     * first valid magnetometer sample (heading), as getRotationMatrix does: no transient.
     */
    FIRST_SAMPLE,
}

/**
 * Immutable, validated settings of [MadgwickFilter]. The defaults are the most accurate single set
 * measured on the BROAD trials (docs/ACCURACY.md); [report] gives the report's own filter.
 *
 * @property mode 6D or 9D. Default [FilterMode.MARG].
 * @property beta β, gain of the normalised gradient step (eq. 42), rad/s: β = √(3/4)·ω̃_β (eq. 50)
 *   with ω̃_β the gyroscope measurement error; the correction turns the estimate at up to 2β rad/s.
 *   ≥ 0. Default 0.02 (ω̃_β ≈ 1.3°/s), possible because the rest estimate removes most gyroscope bias.
 * @property zeta ζ, gain of the report's gyroscope bias drift compensation (eq. 48), rad/s²:
 *   ζ = √(3/4)·ω̃_ζ (eq. 51) with ω̃_ζ the gyroscope drift rate. Acts in MARG steps, as in the report.
 *   0 disables it. ≥ 0. Default 0: on real data it hurts (docs/ACCURACY.md); the rest estimate
 *   replaces it.
 * @property initialisation [Initialisation.FIRST_SAMPLE] by default.
 * @property restBiasEstimation estimate the gyroscope bias while the sensor is at rest.
 * @property restGyroThreshold rest when the gyroscope deviates from its low-passed value, and that
 *   value from zero, by less than this, rad/s. Default 3°/s.
 * @property restAccThreshold rest when the accelerometer deviates from its low-passed value by less
 *   than this, m/s². Default 0.5 m/s².
 * @property restMinTime time the rest conditions must hold before rest is declared, s. Default 1.5 s.
 * @property restBiasTime at rest, the bias is the mean gyroscope reading since rest began, for up to
 *   this long, then a moving average with this time constant, s. Default 2 s.
 * @property magDisturbanceRejection ignore the magnetometer while its magnitude or dip angle
 *   departs from a learned reference (the gyroscope then holds heading).
 * @property magNormTolerance allowed relative deviation of the field magnitude from the reference.
 *   Default 0.1 (10 %).
 * @property magDipTolerance allowed deviation of the dip angle from the reference, rad. Default 10°.
 * @property magMaxRejectionTime after this long continuously disturbed, the current field becomes
 *   the new reference (a new environment), s. Default 60 s.
 * @property magReferenceTime time constant with which the reference follows an undisturbed field,
 *   s. Default 20 s.
 * @property accRejection skip the accelerometer correction during strong non-gravitational
 *   acceleration. Default off: on BROAD it costs more (drift while rejected) than it saves.
 * @property accNormTolerance reject when ‖a‖ departs from standard gravity by more than this, m/s².
 *   Default 2 m/s².
 * @property accAngleTolerance reject when a is further than this from the estimated up, rad.
 *   Default 10°.
 * @property accMaxRejectionTime after this long continuously rejected, the accelerometer is trusted
 *   again (recovery from a wrong estimate), s. Default 5 s.
 * @property outputFrame earth frame of [MadgwickFilter.orientation]. Default [WorldFrame.ENU] (Android's
 *   world); [WorldFrame.NWU] is the report's, [WorldFrame.NED] the aerospace one.
 * @property maxGap longest accepted time between samples, s: a longer gyroscope gap is not
 *   integrated, and an accelerometer or magnetometer sample older than this is not used. Default 0.5 s.
 */
public data class FilterSettings(
    val mode: FilterMode = FilterMode.MARG,
    val beta: Double = 0.02,
    val zeta: Double = 0.0,
    val initialisation: Initialisation = Initialisation.FIRST_SAMPLE,
    val restBiasEstimation: Boolean = true,
    val restGyroThreshold: Double = 3.0 * DEG,
    val restAccThreshold: Double = 0.5,
    val restMinTime: Double = 1.5,
    val restBiasTime: Double = 2.0,
    val magDisturbanceRejection: Boolean = true,
    val magNormTolerance: Double = 0.1,
    val magDipTolerance: Double = 10.0 * DEG,
    val magMaxRejectionTime: Double = 60.0,
    val magReferenceTime: Double = 20.0,
    val accRejection: Boolean = false,
    val accNormTolerance: Double = 2.0,
    val accAngleTolerance: Double = 10.0 * DEG,
    val accMaxRejectionTime: Double = 5.0,
    val outputFrame: WorldFrame = WorldFrame.ENU,
    val maxGap: Double = 0.5,
) {
    init {
        requireFinite("beta", beta, min = 0.0)
        requireFinite("zeta", zeta, min = 0.0)
        requirePositive("restGyroThreshold", restGyroThreshold)
        requirePositive("restAccThreshold", restAccThreshold)
        requireFinite("restMinTime", restMinTime, min = 0.0)
        requirePositive("restBiasTime", restBiasTime)
        requirePositive("magNormTolerance", magNormTolerance)
        require(magDipTolerance > 0.0 && magDipTolerance < PI / 2) { "magDipTolerance must be in (0, π/2) rad: $magDipTolerance" }
        requirePositive("magMaxRejectionTime", magMaxRejectionTime)
        requirePositive("magReferenceTime", magReferenceTime)
        requirePositive("accNormTolerance", accNormTolerance)
        require(accAngleTolerance > 0.0 && accAngleTolerance < PI) { "accAngleTolerance must be in (0, π) rad: $accAngleTolerance" }
        requirePositive("accMaxRejectionTime", accMaxRejectionTime)
        requirePositive("maxGap", maxGap)
    }

    public companion object {
        /**
         * The report's filter exactly: β for ω̃_β = 5°/s and ζ for ω̃_ζ = 0.2°/s² as in its
         * listing (eqs. 50–51; ζ acts in MARG steps only), identity start, none of the additions.
         */
        @JvmStatic
        @JvmOverloads
        public fun report(mode: FilterMode = FilterMode.MARG): FilterSettings = FilterSettings(
            mode = mode,
            beta = SQRT_3_4 * 5.0 * DEG,
            zeta = SQRT_3_4 * 0.2 * DEG,
            initialisation = Initialisation.IDENTITY,
            restBiasEstimation = false,
            magDisturbanceRejection = false,
            accRejection = false,
        )

        private const val DEG = PI / 180.0
        private val SQRT_3_4 = kotlin.math.sqrt(0.75)

        private fun requireFinite(name: String, v: Double, min: Double) =
            require(v.isFinite() && v >= min) { "$name must be finite and ≥ $min: $v" }

        private fun requirePositive(name: String, v: Double) =
            require(v.isFinite() && v > 0.0) { "$name must be finite and > 0: $v" }
    }
}
