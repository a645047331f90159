package dev.motionfusion.app.settings

import dev.motionfusion.app.live.AngleConvention
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.sensor.SamplingRate
import dev.motionfusion.core.filter.FilterMode
import dev.motionfusion.core.filter.FilterSettingDescriptors

/** A field of the settings form that can hold an invalid entry. */
enum class SettingsField { BETA, ZETA, RATE_HZ }

/** The settings form's raw entries (text as typed), turned into [LiveSettings] by [parse]. */
data class SettingsForm(
    val beta: String,
    val zeta: String,
    val nineD: Boolean,
    val restBias: Boolean,
    val magRejection: Boolean,
    val accRejection: Boolean,
    val convention: AngleConvention,
    /** A named delay, or null for a rate in Hz given by [rateHz]. */
    val delay: SamplingRate.Delay?,
    val rateHz: String,
) {
    /** Either valid settings or the fields in error (each with why). */
    sealed interface Result {
        data class Valid(val settings: LiveSettings) : Result
        data class Invalid(val errors: Map<SettingsField, String>) : Result
    }

    fun parse(): Result {
        val errors = LinkedHashMap<SettingsField, String>()
        val b = number(beta)
        refusal("beta", b, LiveSettings.MAX_BETA)?.let { errors[SettingsField.BETA] = it }
        val z = number(zeta)
        refusal("zeta", z, LiveSettings.MAX_ZETA)?.let { errors[SettingsField.ZETA] = it }
        var rate: SamplingRate? = delay
        if (delay == null) {
            val hz = rateHz.trim().toIntOrNull()
            if (hz == null || hz !in SamplingRate.MIN_HZ..SamplingRate.MAX_HZ) {
                errors[SettingsField.RATE_HZ] = "rate: a whole number of Hz from ${SamplingRate.MIN_HZ} to ${SamplingRate.MAX_HZ}"
            } else {
                rate = SamplingRate.Hz(hz)
            }
        }
        if (errors.isNotEmpty()) return Result.Invalid(errors)
        return Result.Valid(
            LiveSettings(
                beta = b!!,
                zeta = z!!,
                mode = if (nineD) FilterMode.MARG else FilterMode.IMU,
                restBiasEstimation = restBias,
                magDisturbanceRejection = magRejection,
                accRejection = accRejection,
                convention = convention,
                rate = rate!!,
            ),
        )
    }

    companion object {
        /** The form showing [s]. */
        fun of(s: LiveSettings): SettingsForm = SettingsForm(
            beta = s.beta.toString(),
            zeta = s.zeta.toString(),
            nineD = s.mode == FilterMode.MARG,
            restBias = s.restBiasEstimation,
            magRejection = s.magDisturbanceRejection,
            accRejection = s.accRejection,
            convention = s.convention,
            delay = s.rate as? SamplingRate.Delay,
            rateHz = (s.rate as? SamplingRate.Hz)?.hz?.toString() ?: "",
        )

        /**
         * Why [v] cannot be the filter setting [name]: not a number, refused by fusion-core's
         * FilterSettings (through its settings table), or above the app's bound [max]; null if fine.
         */
        private fun refusal(name: String, v: Double?, max: Double): String? {
            val d = FilterSettingDescriptors.named(name) ?: error("no filter setting $name")
            if (v == null) return "$name: a number in ${d.unit}"
            try {
                d.with(LiveSettings.DEFAULT_FILTER, v)
            } catch (e: IllegalArgumentException) {
                return e.message
            }
            return if (v > max) "$name: at most $max ${d.unit}" else null
        }

        /** A finite number, accepting a decimal comma; null otherwise. */
        private fun number(text: String): Double? = text.trim().replace(',', '.').toDoubleOrNull()?.takeIf { it.isFinite() }
    }
}
