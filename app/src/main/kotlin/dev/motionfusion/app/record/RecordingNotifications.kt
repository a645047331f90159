package dev.motionfusion.app.record

import android.app.Notification
import android.content.Context
import android.content.Intent
import android.text.format.DateUtils
import androidx.core.app.NotificationCompat
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.Clock
import dev.motionfusion.app.platform.Foreground
import dev.motionfusion.app.platform.ForegroundLifecycle
import dev.motionfusion.core.session.Continuation

/**
 * The recording's notifications (docs/RECORDING.md): the ongoing one with the elapsed time, the number of samples, a
 * resumed recording's gap and a Stop action; the alert of a recording that ended by itself or could not start; and
 * "Recording interrupted — tap to continue". Every PendingIntent is immutable. Main thread.
 */
internal class RecordingNotifications(private val context: Context, private val clock: Clock) {
    /** The ongoing notification's builder: made once with its PendingIntents; an update only sets the text. */
    private var ongoing: NotificationCompat.Builder? = null

    /**
     * The ongoing notification of a recording started at [startedWallMs] / [startedElapsedMs] (0: not yet) with [rows]
     * written; a resumed one ([continues]) or one being resumed ([resuming]) says so.
     */
    fun ongoing(startedWallMs: Long, startedElapsedMs: Long, rows: Long, continues: Continuation?, resuming: Boolean): Notification {
        val elapsedS = if (startedElapsedMs == 0L) 0 else (clock.elapsedRealtimeNanos() / 1_000_000 - startedElapsedMs) / 1000
        val builder = ongoing ?: NotificationCompat.Builder(context, Foreground.CHANNEL_RECORDING)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(context.getString(R.string.record_notification_title))
            .setOngoing(true)
            .setOnlyAlertOnce(true)
            .setShowWhen(true)
            .setUsesChronometer(true)
            .setCategory(NotificationCompat.CATEGORY_SERVICE)
            .setForegroundServiceBehavior(NotificationCompat.FOREGROUND_SERVICE_IMMEDIATE)
            .setContentIntent(openApp())
            .addAction(
                0, context.getString(R.string.record_stop),
                ForegroundLifecycle.serviceAction(context, 1, Intent(context, RecordingService::class.java).setAction(RecordingService.ACTION_STOP)),
            )
            .also { ongoing = it }
        // The chronometer counts the time on the shade by itself; the text's time and count are as of this update.
        return builder
            .setWhen(startedWallMs)
            .setContentText(context.getString(R.string.record_notification_text, DateUtils.formatElapsedTime(elapsedS), rows))
            // A resumed recording says so (the state changes from resuming to resumed, so it is set on every update).
            .setSubText(continues?.let { context.getString(R.string.record_resumed_short, RecordingService.gapText(it)) } ?: if (resuming) context.getString(R.string.record_resuming) else null)
            .build()
    }

    /** A recording that could not start or ended by itself ([failed]: a failure, else a limit). */
    fun alert(text: String, failed: Boolean = true): Notification =
        NotificationCompat.Builder(context, Foreground.CHANNEL_ALERTS)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(context.getString(if (failed) R.string.record_failed_title else R.string.record_limit_title))
            .setContentText(text)
            .setStyle(NotificationCompat.BigTextStyle().bigText(text))
            .setAutoCancel(true)
            .setContentIntent(openApp())
            .build()

    /** "Recording interrupted — tap to continue": the tap starts the service in the foreground, which Android 12+ allows from a notification. */
    fun interrupted(): Notification {
        val text = context.getString(R.string.record_interrupted_text)
        return NotificationCompat.Builder(context, Foreground.CHANNEL_ALERTS)
            .setSmallIcon(R.drawable.ic_record)
            .setContentTitle(context.getString(R.string.record_interrupted_title))
            .setContentText(text)
            .setStyle(NotificationCompat.BigTextStyle().bigText(text))
            .setAutoCancel(true)
            .setCategory(NotificationCompat.CATEGORY_ERROR)
            .setContentIntent(continueIntent(context))
            .build()
    }

    /** The app's launcher screen (the live screen), named by the manifest rather than by class: record does not depend on the screens. */
    private fun openApp() = ForegroundLifecycle.openScreen(
        context,
        context.packageManager.getLaunchIntentForPackage(context.packageName) ?: Intent().setPackage(context.packageName),
    )

    companion object {
        /** The tap of the interrupted notification: the service, started in the foreground ([RecordingService.ACTION_CONTINUE]). */
        fun continueIntent(context: Context) = ForegroundLifecycle.foregroundServiceAction(
            context, 2, Intent(context, RecordingService::class.java).setAction(RecordingService.ACTION_CONTINUE),
        )
    }
}
