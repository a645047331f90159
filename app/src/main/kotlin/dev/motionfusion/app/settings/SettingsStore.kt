package dev.motionfusion.app.settings

import android.content.Context
import android.content.SharedPreferences
import dev.motionfusion.app.platform.MainThreadPolicy

/**
 * [LiveSettings] persisted in SharedPreferences, one text entry per [Setting] under its key
 * (numbers as exact, locale-independent doubles; flags as true/false; choices by name). A stored
 * value that is missing or refused keeps its default, so a damaged file never stops the app; a
 * value kept under a key of an earlier version ([LEGACY]) is still read.
 *
 * The file is opened on first use, and every call touches it: off the main thread only
 * ([SettingsRepository] calls it on the disk executor).
 */
class SettingsStore(open: () -> SharedPreferences, private val settings: List<Setting> = Setting.ALL) {
    constructor(context: Context) : this({ context.getSharedPreferences(FILE, Context.MODE_PRIVATE) })

    private val file by lazy(open)

    private val prefs: SharedPreferences get() {
        MainThreadPolicy.checkNotMainThread()
        return file
    }

    fun load(): LiveSettings {
        val stored = prefs.all
        var s = LiveSettings()
        for (setting in settings) {
            val text = (stored[setting.key] ?: stored[LEGACY[setting.key]])?.toString() ?: continue
            s = try {
                setting.withText(s, text)
            } catch (e: IllegalArgumentException) {
                s
            }
        }
        return s
    }

    fun save(s: LiveSettings) {
        val e = prefs.edit()
        for (setting in settings) e.putString(setting.key, setting.text(s))
        for (old in LEGACY.values) e.remove(old)
        e.apply()
    }

    /** True once the user answered the notification-permission explanation (it is shown once). */
    fun loadNotificationsAnswered(): Boolean = prefs.getBoolean(NOTIFICATIONS_ANSWERED, false)

    fun saveNotificationsAnswered() {
        prefs.edit().putBoolean(NOTIFICATIONS_ANSWERED, true).apply()
    }

    /** The last `host:port` the Stream screen pushed UDP to ("" before the first). */
    fun loadUdpTarget(): String = prefs.getString(UDP_TARGET, null) ?: ""

    fun saveUdpTarget(target: String) {
        prefs.edit().putString(UDP_TARGET, target).apply()
    }

    companion object {
        const val FILE = "live_settings"
        private const val NOTIFICATIONS_ANSWERED = "notifications_answered"
        private const val UDP_TARGET = "stream_udp_target"

        /** Keys of the first settings screen, by the key that replaced them. */
        private val LEGACY = mapOf(
            "rest_bias_estimation" to "rest_bias",
            "mag_disturbance_rejection" to "mag_rejection",
        )
    }
}
