package dev.motionfusion.app.settings

import kotlinx.coroutines.CoroutineDispatcher
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Job
import kotlinx.coroutines.flow.MutableStateFlow
import kotlinx.coroutines.flow.StateFlow
import kotlinx.coroutines.flow.asStateFlow
import kotlinx.coroutines.launch
import kotlinx.coroutines.withContext

/**
 * The user's settings, one source for the whole app: the live filter, the recording (whose
 * meta.json gets them, with their recording limits) and the settings screen read [settings];
 * [update] publishes and persists.
 *
 * The store is read on [io] when the repository is made (as a DataStore's first read): until
 * then [settings] holds the defaults, which the live screen shows for those first moments; what
 * must not start on defaults (a recording) waits for [awaitLoaded]. A change made before the
 * read completes wins over the stored value. [update] and [markNotificationsAnswered] are called
 * on the main thread ([scope]'s); the store's writes run on [io].
 */
class SettingsRepository(private val store: SettingsStore, private val io: CoroutineDispatcher, private val scope: CoroutineScope) {
    private val flow = MutableStateFlow(LiveSettings())
    private var changedBeforeLoad = false

    val settings: StateFlow<LiveSettings> = flow.asStateFlow()

    private val loaded: Job = scope.launch {
        val (stored, answered, target) = withContext(io) { Triple(store.load(), store.loadNotificationsAnswered(), store.loadUdpTarget()) }
        if (!changedBeforeLoad) flow.value = stored
        if (answered) notificationsAnswered = true
        if (udpTarget.isEmpty()) udpTarget = target
    }

    /** Waits until the stored settings have been read (at once when they have). */
    suspend fun awaitLoaded(): Unit = loaded.join()

    /** Hands [s] to every reader at once and stores it on [io]. Main thread. */
    fun update(s: LiveSettings) {
        changedBeforeLoad = true
        flow.value = s
        scope.launch(io) {
            // Stores the latest settings, whatever order the writes run in ([io] need not be serial).
            synchronized(writing) { store.save(flow.value) }
        }
    }

    private val writing = Any()

    /** True once the user answered the notification-permission explanation before a first recording. */
    @Volatile var notificationsAnswered: Boolean = false
        private set

    /** Main thread. */
    fun markNotificationsAnswered() {
        notificationsAnswered = true
        scope.launch(io) { store.saveNotificationsAnswered() }
    }

    /** The last `host:port` a UDP push started to ("" before the first, and until the store has been read). */
    @Volatile var udpTarget: String = ""
        private set

    /** Keeps [target] as the Stream screen's UDP target for next time. Main thread. */
    fun rememberUdpTarget(target: String) {
        if (target == udpTarget) return
        udpTarget = target
        scope.launch(io) { synchronized(writing) { store.saveUdpTarget(udpTarget) } }
    }

    /** What the settings screen needs, from the application's object graph. */
    interface Provider {
        val settingsRepository: SettingsRepository
    }
}
