package dev.motionfusion.app.stream

import androidx.annotation.StringRes
import android.app.Notification
import android.app.PendingIntent
import android.app.Service
import android.content.Context
import android.content.Intent
import android.content.pm.ServiceInfo
import android.net.wifi.WifiManager
import android.os.Build
import android.os.IBinder
import androidx.core.app.NotificationCompat
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.Clock
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.platform.ForegroundLifecycle
import dev.motionfusion.stream.StreamClientInfo
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.SupervisorJob
import kotlinx.coroutines.cancel
import kotlinx.coroutines.delay
import kotlinx.coroutines.launch

/** What the stream's service needs, from the application's object graph. */
internal interface StreamDependencies {
    val streamController: StreamController
    val clock: Clock

    /** Enters the foreground (ServiceCompat.startForeground); tests make it refuse as the system can. */
    fun startForeground(service: Service, id: Int, notification: Notification, type: Int)

    /** The Wi-Fi locks ([StreamService.systemWifiLocks]; tests record the modes). */
    val wifiLocks: WifiLocks

    /** Implemented by the application. */
    interface Provider {
        val streamDependencies: StreamDependencies
    }
}

/** Takes Wi-Fi locks. */
internal fun interface WifiLocks {
    /** Takes a lock of [mode] (a `WifiManager.WIFI_MODE_*`) named [tag]; returns what releases it, or null when the phone has no Wi-Fi. */
    fun acquire(mode: Int, tag: String): (() -> Unit)?
}

/**
 * Keeps the live stream going with the screen off and the app in the background: a foreground service
 * of type `connectedDevice` (a link to the laptop), started by [StreamController.start],
 * that holds a partial wake lock (renewed while streaming; the foreground, its notification and the wake lock are
 * the app's one [ForegroundLifecycle]) and Wi-Fi locks
 * ([wifiLockModes]) and shows an ongoing notification with the clients and a Stop action. It follows
 * the controller's state and ends itself when streaming is off, however it was turned off (the
 * screen's switch, the notification's Stop, a failure). The controller does not depend on it: a
 * refused foreground start stops the stream and is shown on the Stream screen. Not sticky: a killed
 * process loses its server and pairing code, so nothing is resumed.
 *
 * Recording and streaming together are two services, each holding the capture for itself.
 */
class StreamService : Service() {
    private val scope = CoroutineScope(SupervisorJob() + Dispatchers.Main.immediate)
    private lateinit var deps: StreamDependencies
    private lateinit var foreground: ForegroundLifecycle
    /** The Wi-Fi locks held, with their modes. */
    private val wifiLocks = ArrayList<Pair<Int, () -> Unit>>()
    private var begun = false
    private var ended = false
    private var ongoing: NotificationCompat.Builder? = null
    private var shownText: String? = null

    /** Notifications posted by updates (for tests: one per change of what it says, not one a second). */
    internal var notificationUpdates = 0
        private set

    override fun onCreate() {
        super.onCreate()
        deps = (application as StreamDependencies.Provider).streamDependencies
        foreground = ForegroundLifecycle(this, NOTIFICATION_ID, FOREGROUND_SERVICE_TYPE, "MotionFusion:streaming", deps.clock, deps::startForeground)
    }

    override fun onBind(intent: Intent?): IBinder? = null

    override fun onStartCommand(intent: Intent?, flags: Int, startId: Int): Int {
        when (intent?.action) {
            // The notification's Stop: the service ends when the controller is off.
            ACTION_STOP -> {
                deps.streamController.stop()
                if (!begun) stopSelf()
            }
            // The notification's answer to a laptop that asks to connect.
            ACTION_ALLOW, ACTION_DENY -> {
                val id = intent.getLongExtra(EXTRA_CLIENT, -1)
                if (intent.action == ACTION_ALLOW) deps.streamController.allow(id) else deps.streamController.deny(id)
                if (!begun) stopSelf()
            }
            else -> begin()
        }
        return START_NOT_STICKY
    }

    /** Foreground at once (startForegroundService() must be answered within seconds), then the locks, then follows the controller. */
    private fun begin() {
        if (begun) return
        begun = true
        val controller = deps.streamController
        foreground.enter(notification(controller.state.value))?.let { refusal ->
            controller.stop(failure = refusal.text)
            end()
            return
        }
        foreground.holdWakeLock()
        holdWifiLocks()
        scope.launch {
            controller.state.collect { s ->
                when (s) {
                    StreamState.Off, is StreamState.Failed -> end()
                    else -> update(s)
                }
            }
        }
        // On a timer, not on the state: while nothing changes (no client yet) the state emits nothing.
        scope.launch {
            while (true) {
                delay(RENEW_TICK_MS)
                foreground.renewWakeLockIfDue()
            }
        }
    }

    /** Keeps Wi-Fi out of power save while streaming ([wifiLockModes]); none on a phone without Wi-Fi. */
    private fun holdWifiLocks() {
        for (mode in wifiLockModes(Build.VERSION.SDK_INT)) {
            deps.wifiLocks.acquire(mode, "MotionFusion:streaming")?.let { wifiLocks += mode to it }
        }
    }

    private fun end() {
        if (ended) return
        ended = true
        releaseWifiLocks()
        scope.cancel()
        foreground.leave()
    }

    private fun releaseWifiLocks() {
        for ((_, release) in wifiLocks) release()
        wifiLocks.clear()
    }

    override fun onDestroy() {
        foreground.releaseWakeLock()
        releaseWifiLocks()
        scope.cancel()
        super.onDestroy()
    }

    private fun update(state: StreamState) {
        // The request's id too: a new request with the same text needs the notification's answers anew.
        if (text(state) + asking(state)?.id == shownText) return
        notificationUpdates++
        foreground.notify(notification(state))
    }

    /**
     * What the notification says: a laptop that asks to connect, or the paired clients (stalled ones named) and the code,
     * or that the server starts or stops.
     */
    private fun text(state: StreamState): String = when (state) {
        is StreamState.On -> asking(state)?.let { r ->
            r.name?.let { getString(R.string.stream_notification_request, it, r.address) } ?: getString(R.string.stream_notification_request_unnamed, r.address)
        } ?: run {
            val paired = state.clients.filter { it.paired }
            val stalled = paired.count { it.stalled }
            val clients = if (paired.isEmpty()) getString(R.string.stream_notification_waiting)
            else resources.getQuantityString(R.plurals.stream_notification_clients, paired.size, paired.size)
            val line = getString(R.string.stream_notification_text, clients, state.code)
            if (stalled == 0) line else getString(R.string.stream_notification_stalled, line, stalled)
        }
        StreamState.Stopping -> getString(R.string.stream_stopping)
        else -> getString(R.string.stream_starting)
    }

    /** The first laptop that asks to connect, answered from the notification. */
    private fun asking(state: StreamState): StreamClientInfo? = (state as? StreamState.On)?.clients?.firstOrNull { it.awaitingConfirmation }

    private fun notification(state: StreamState): Notification {
        val text = text(state)
        shownText = text + asking(state)?.id
        val builder = ongoing ?: NotificationCompat.Builder(this, Foreground.CHANNEL_STREAMING)
            .setSmallIcon(R.drawable.ic_stream)
            .setContentTitle(getString(R.string.stream_notification_title))
            .setOngoing(true)
            .setOnlyAlertOnce(true)
            .setCategory(NotificationCompat.CATEGORY_SERVICE)
            .setForegroundServiceBehavior(NotificationCompat.FOREGROUND_SERVICE_IMMEDIATE)
            .setContentIntent(ForegroundLifecycle.openScreen(this, Intent(this, StreamActivity::class.java)))
            .also { ongoing = it }
        builder.clearActions()
        // Deny and Allow while a laptop asks (immutable: the request's id is fixed when the notification is posted).
        asking(state)?.let { r ->
            builder.addAction(0, getString(R.string.stream_deny), answer(ACTION_DENY, 2, r.id))
            builder.addAction(0, getString(R.string.stream_allow), answer(ACTION_ALLOW, 3, r.id))
        }
        builder.addAction(0, getString(R.string.stream_stop), ForegroundLifecycle.serviceAction(this, 1, Intent(this, StreamService::class.java).setAction(ACTION_STOP)))
        // On the lock screen the pairing code stays hidden: there the public version, without it, is shown.
        val public = NotificationCompat.Builder(this, Foreground.CHANNEL_STREAMING)
            .setSmallIcon(R.drawable.ic_stream)
            .setContentTitle(getString(R.string.stream_notification_title))
            .setCategory(NotificationCompat.CATEGORY_SERVICE)
            .build()
        return builder.setContentText(text).setVisibility(NotificationCompat.VISIBILITY_PRIVATE).setPublicVersion(public).build()
    }

    private fun answer(action: String, requestCode: Int, id: Long): PendingIntent =
        ForegroundLifecycle.serviceAction(this, requestCode, Intent(this, StreamService::class.java).setAction(action).putExtra(EXTRA_CLIENT, id))

    companion object {
        internal const val ACTION_START = "dev.motionfusion.app.stream.START"
        internal const val ACTION_STOP = "dev.motionfusion.app.stream.STOP"
        internal const val ACTION_ALLOW = "dev.motionfusion.app.stream.ALLOW"
        internal const val ACTION_DENY = "dev.motionfusion.app.stream.DENY"

        /** The id of the laptop answered ([StreamClientInfo.id]), with [ACTION_ALLOW] and [ACTION_DENY]. */
        internal const val EXTRA_CLIENT = "client"
        internal const val NOTIFICATION_ID = 7004

        /** How often the wake lock's renewal is looked at (it renews once a minute of the clock). */
        internal const val RENEW_TICK_MS = 10_000L

        /** The manifest's android:foregroundServiceType: connectedDevice, a link to another device (ForegroundServiceTest). */
        internal const val FOREGROUND_SERVICE_TYPE = ServiceInfo.FOREGROUND_SERVICE_TYPE_CONNECTED_DEVICE

        /**
         * The Wi-Fi locks held while streaming, by API level. `WIFI_MODE_FULL_HIGH_PERF` keeps Wi-Fi out of
         * power save with the screen off; Android 14 deprecated it and treats it as `WIFI_MODE_FULL_LOW_LATENCY`
         * (API 29+), which works only while the screen is on and the app in the foreground. So: high-perf
         * below 29; both on 29–33 (low latency with the screen on, high-perf when it is off); low latency
         * from 34 (with the screen off the partial wake lock and the foreground service are what remain).
         */
        @Suppress("DEPRECATION")
        internal fun wifiLockModes(sdk: Int): List<Int> = when {
            sdk < 29 -> listOf(WifiManager.WIFI_MODE_FULL_HIGH_PERF)
            sdk < 34 -> listOf(WifiManager.WIFI_MODE_FULL_HIGH_PERF, WifiManager.WIFI_MODE_FULL_LOW_LATENCY)
            else -> listOf(WifiManager.WIFI_MODE_FULL_LOW_LATENCY)
        }

        /** The phone's Wi-Fi locks (WifiManager, of the application context). */
        internal fun systemWifiLocks(context: Context): WifiLocks = WifiLocks { mode, tag ->
            val wifi = context.applicationContext.getSystemService(WifiManager::class.java) ?: return@WifiLocks null
            val lock = wifi.createWifiLock(mode, tag)
            lock.setReferenceCounted(false)
            lock.acquire()
            val release: () -> Unit = { if (lock.isHeld) lock.release() }
            release
        }

        /**
         * Starts the service (from [StreamController.start], a user's action: Android 12+ forbids a start from
         * the background). Returns why the system refused (a string resource; the exception goes to the log), or null.
         */
        @StringRes
        fun start(context: Context): Int? = ForegroundLifecycle.start(context, Intent(context, StreamService::class.java).setAction(ACTION_START))?.text
    }
}
