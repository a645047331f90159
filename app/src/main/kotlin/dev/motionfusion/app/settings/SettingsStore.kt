package dev.motionfusion.app.settings

import android.content.Context
import android.content.SharedPreferences
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.sensor.SamplingRate

/**
 * [LiveSettings] persisted in SharedPreferences. Numbers are stored as text (exact doubles,
 * locale-independent). A stored value that is missing or invalid falls back to its default, so a
 * damaged file never stops the app.
 */
class SettingsStore(private val prefs: SharedPreferences) {
    constructor(context: Context) : this(context.getSharedPreferences(FILE, Context.MODE_PRIVATE))

    fun load(): LiveSettings {
        val d = LiveSettings()
        val beta = prefs.getString(BETA, null)?.toDoubleOrNull()?.takeIf { it.isFinite() && it in 0.0..LiveSettings.MAX_BETA } ?: d.beta
        val zeta = prefs.getString(ZETA, null)?.toDoubleOrNull()?.takeIf { it.isFinite() && it in 0.0..LiveSettings.MAX_ZETA } ?: d.zeta
        return LiveSettings(
            beta = beta,
            zeta = zeta,
            mode = enumOr(prefs.getString(MODE, null), d.mode),
            restBiasEstimation = prefs.getBoolean(REST_BIAS, d.restBiasEstimation),
            magDisturbanceRejection = prefs.getBoolean(MAG_REJECTION, d.magDisturbanceRejection),
            accRejection = prefs.getBoolean(ACC_REJECTION, d.accRejection),
            convention = enumOr(prefs.getString(CONVENTION, null), d.convention),
            rate = prefs.getString(RATE, null)?.let(SamplingRate::parse) ?: d.rate,
        )
    }

    fun save(s: LiveSettings) {
        prefs.edit()
            .putString(BETA, s.beta.toString())
            .putString(ZETA, s.zeta.toString())
            .putString(MODE, s.mode.name)
            .putBoolean(REST_BIAS, s.restBiasEstimation)
            .putBoolean(MAG_REJECTION, s.magDisturbanceRejection)
            .putBoolean(ACC_REJECTION, s.accRejection)
            .putString(CONVENTION, s.convention.name)
            .putString(RATE, s.rate.key)
            .apply()
    }

    private inline fun <reified E : Enum<E>> enumOr(name: String?, default: E): E =
        enumValues<E>().firstOrNull { it.name == name } ?: default

    companion object {
        const val FILE = "live_settings"
        private const val BETA = "beta"
        private const val ZETA = "zeta"
        private const val MODE = "mode"
        private const val REST_BIAS = "rest_bias"
        private const val MAG_REJECTION = "mag_rejection"
        private const val ACC_REJECTION = "acc_rejection"
        private const val CONVENTION = "convention"
        private const val RATE = "rate"

    }
}
