package dev.motionfusion.app.platform

import android.app.Notification
import android.app.NotificationManager
import android.app.PendingIntent
import android.app.Service
import android.content.Context
import android.content.Intent
import androidx.core.app.ServiceCompat
import androidx.core.content.ContextCompat

/**
 * The one foreground-service lifecycle of the app, owned by each of its services (the recording's, docs/RECORDING.md,
 * and the live stream's, docs/STREAMING.md): entering the foreground with the manifest's [type] and its ongoing
 * notification [notificationId] (the channels created first; a refusal returned as [Foreground.Refusal]), the partial
 * wake lock that times out unless renewed ([RenewedWakeLock], named [wakeLockTag]), the service's other notifications,
 * and leaving: the wake lock let go, the ongoing notification removed, the service stopped. [starter] enters the
 * foreground (ServiceCompat.startForeground; tests make it refuse as the system can). Main thread.
 */
class ForegroundLifecycle(
    private val service: Service,
    private val notificationId: Int,
    private val type: Int,
    wakeLockTag: String,
    clock: Clock,
    private val starter: (Service, Int, Notification, Int) -> Unit,
) {
    private val wakeLock = RenewedWakeLock(service, wakeLockTag, clock)

    private val notifications: NotificationManager get() = service.getSystemService(NotificationManager::class.java)

    /**
     * Creates the notification channels and enters the foreground showing [ongoing] (startForegroundService() must be
     * answered within seconds: first thing). Returns why the system refused, or null ([Foreground.enter]).
     */
    fun enter(ongoing: Notification): Foreground.Refusal? {
        Foreground.createChannels(service)
        return Foreground.enter(service, notificationId, ongoing, type, starter)
    }

    /** Takes the wake lock (again, with a fresh timeout, when held). */
    fun holdWakeLock() = wakeLock.hold()

    /** Renews the wake lock's timeout when due; nothing when it is not held. */
    fun renewWakeLockIfDue() = wakeLock.renewIfDue()

    /**
     * The wake lock only while [needed] (a recording's sensors that cannot wake the phone for their batches themselves,
     * `WakeLockNeed`): let go when not, taken when needed and not held, renewed when due while held.
     */
    fun keepWakeLock(needed: Boolean) {
        when {
            !needed -> wakeLock.release()
            wakeLock.isHeld -> wakeLock.renewIfDue()
            else -> wakeLock.hold()
        }
    }

    fun releaseWakeLock() = wakeLock.release()

    /** Shows [notification] as [id] (the ongoing one by default: an update of its text). */
    fun notify(notification: Notification, id: Int = notificationId) = notifications.notify(id, notification)

    fun cancel(id: Int) = notifications.cancel(id)

    /** The service is done: the wake lock let go, the foreground and its notification left, the service stopped. */
    fun leave() {
        wakeLock.release()
        ServiceCompat.stopForeground(service, ServiceCompat.STOP_FOREGROUND_REMOVE)
        service.stopSelf()
    }

    companion object {
        /**
         * Starts a foreground service with [intent] (from a user's action: Android 12+ forbids a start from the
         * background). Returns why the system refused (the exception goes to the log), or null.
         */
        fun start(context: Context, intent: Intent): Foreground.Refusal? = try {
            ContextCompat.startForegroundService(context, intent)
            null
        } catch (e: IllegalStateException) {
            Foreground.Refusal.of(e, intent.component?.className?.substringAfterLast('.') ?: "service")
        }

        /** An action of a notification that goes to a service: immutable, its extras replaced by the latest. */
        fun serviceAction(context: Context, requestCode: Int, intent: Intent): PendingIntent =
            PendingIntent.getService(context, requestCode, intent, PendingIntent.FLAG_IMMUTABLE or PendingIntent.FLAG_UPDATE_CURRENT)

        /** The same, starting the service in the foreground (which Android 12+ allows from a notification's tap). */
        fun foregroundServiceAction(context: Context, requestCode: Int, intent: Intent): PendingIntent =
            PendingIntent.getForegroundService(context, requestCode, intent, PendingIntent.FLAG_IMMUTABLE or PendingIntent.FLAG_UPDATE_CURRENT)

        /** A notification's tap that opens a screen of the app (immutable; one already on top is reused). */
        fun openScreen(context: Context, intent: Intent): PendingIntent =
            PendingIntent.getActivity(context, 0, intent.addFlags(Intent.FLAG_ACTIVITY_SINGLE_TOP), PendingIntent.FLAG_IMMUTABLE)
    }
}
