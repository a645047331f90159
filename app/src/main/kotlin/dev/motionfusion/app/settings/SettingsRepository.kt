package dev.motionfusion.app.settings

import dev.motionfusion.app.live.LiveSettings
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
    }

    /** What the settings screen needs, from the application's object graph. */
    interface Provider {
        val settingsRepository: SettingsRepository
    }
}
