package dev.motionfusion.app.settings

import dev.motionfusion.app.live.LiveSettings
import dev.motionfusion.app.live.RecordingLimits
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow

/**
 * The user's settings, one source for the whole app: the live filter, the recording (whose
 * meta.json gets them) and the settings screen read [settings]; [update] persists and publishes.
 */
class SettingsRepository(private val store: SettingsStore) {
    private val flow = MutableStateFlow(store.load())

    val settings: StateFlow<LiveSettings> = flow.asStateFlow()

    /** Stores [s] (SharedPreferences writes it in the background) and hands it to every reader at once. */
    fun update(s: LiveSettings) {
        store.save(s)
        flow.value = s
        limitsFlow.value = s.limits
    }

    private val limitsFlow = MutableStateFlow(flow.value.limits)

    /** When recordings stop by themselves (part of [settings]); a recording takes them when it starts. */
    val recordingLimits: StateFlow<RecordingLimits> = limitsFlow.asStateFlow()

    fun updateLimits(l: RecordingLimits) = update(settings.value.copy(limits = l))

    /** True once the user answered the notification-permission explanation before a first recording. */
    @Volatile var notificationsAnswered: Boolean = store.loadNotificationsAnswered()
        private set

    fun markNotificationsAnswered() {
        store.saveNotificationsAnswered()
        notificationsAnswered = true
    }

    /** What the settings screen needs, from the application's object graph. */
    interface Provider {
        val settingsRepository: SettingsRepository
    }
}
