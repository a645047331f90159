package dev.motionfusion.app.settings

import android.content.Context
import android.content.SharedPreferences
import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.platform.MainThreadPolicy
import dev.motionfusion.app.record.RecordingLimits
import dev.motionfusion.app.sensor.SamplingRate

/**
 * [LiveSettings] persisted in SharedPreferences. Numbers are stored as text (exact doubles,
 * locale-independent). A stored value that is missing or invalid falls back to its default, so a
 * damaged file never stops the app.
 */
class SettingsStore(private val prefs: SharedPreferences) {
    /** Reads the file at once (MainThreadPolicy's one exemption: the settings are needed before the first frame). */
    constructor(context: Context) : this(
        MainThreadPolicy.allowingDiskReads { context.getSharedPreferences(FILE, Context.MODE_PRIVATE).also { it.all } },
    )

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

    /** The recording limits; a stored value that is not valid falls back to its default. */
    fun loadLimits(): RecordingLimits {
        val d = RecordingLimits()
        return RecordingLimits(
            maxDurationS = prefs.getString(MAX_DURATION_S, null)?.toLongOrNull()?.takeIf { it in 0L..RecordingLimits.MAX_DURATION_LIMIT_S } ?: d.maxDurationS,
            stopBatteryPercent = prefs.getString(STOP_BATTERY, null)?.toIntOrNull()?.takeIf { it in 0..RecordingLimits.MAX_STOP_BATTERY_PERCENT }
                ?: d.stopBatteryPercent,
        )
    }

    fun saveLimits(l: RecordingLimits) {
        prefs.edit()
            .putString(MAX_DURATION_S, l.maxDurationS.toString())
            .putString(STOP_BATTERY, l.stopBatteryPercent.toString())
            .apply()
    }

    /** True once the user answered the notification-permission explanation (it is shown once). */
    fun loadNotificationsAnswered(): Boolean = prefs.getBoolean(NOTIFICATIONS_ANSWERED, false)

    fun saveNotificationsAnswered() {
        prefs.edit().putBoolean(NOTIFICATIONS_ANSWERED, true).apply()
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
        private const val MAX_DURATION_S = "max_duration_s"
        private const val STOP_BATTERY = "stop_battery_percent"
        private const val NOTIFICATIONS_ANSWERED = "notifications_answered"

    }
}
