package dev.motionfusion.app.record

import dev.motionfusion.app.ui.setTextIfChanged
import dev.motionfusion.app.settings.RecordingLimits
import dev.motionfusion.app.ui.stackWhenCrowded
import android.content.Context
import android.content.Intent
import android.content.res.ColorStateList
import android.os.Handler
import android.os.Looper
import android.text.InputFilter
import android.text.InputType
import android.text.format.DateUtils
import android.view.LayoutInflater
import android.view.View
import android.view.ViewGroup
import android.widget.Button
import android.widget.EditText
import android.widget.TextView
import androidx.activity.ComponentActivity
import androidx.appcompat.app.AlertDialog
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.LifecycleEventObserver
import com.google.android.material.dialog.MaterialAlertDialogBuilder
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.NotificationAsk
import dev.motionfusion.app.sessions.SessionDetailActivity
import dev.motionfusion.app.sessions.SessionsActivity
import dev.motionfusion.core.session.SessionMarkers

/**
 * The Record/Stop button, the Mark button (while recording: a tap marks the moment, a long
 * press marks it and asks for a note), the recording status and the way to the sessions list,
 * inflated into a host activity's container (the main screen's `record_bar`). It shows
 * [Recordings.state] (refreshed twice a second while attached to a window, for the elapsed
 * time); the recording itself lives in [RecordingService] and does not depend on this view or
 * its activity.
 *
 * With a start delay set ("Start recording after"), Record counts down first ([StartCountdown]): the seconds left in
 * the status line and on the button, which cancels the countdown; leaving the screen cancels it too (not a rotation),
 * since Android 12+ would refuse the recording's foreground service to an app in the background.
 *
 * After Stop it offers the saved session: Open (its detail screen) and Share (the same, its Share
 * started at once). Stop asks first ([confirmStop]).
 *
 * On Android 13+ the first Record explains the recording's notification before the system asks
 * for the permission ([NotificationAsk]); recording starts after the answer, whatever it is, and
 * the question is not asked again. Without the permission the bar says that the notification may
 * be hidden and offers to turn notifications on (the app's notification settings).
 */
internal class RecordBar private constructor(private val activity: ComponentActivity, private val root: View) {
    private val toggle: Button = root.findViewById(R.id.record_toggle)
    private val markButton: Button = root.findViewById(R.id.record_mark)
    private val status: TextView = root.findViewById(R.id.record_status)
    private val after: View = root.findViewById(R.id.record_after)
    private val notificationsOn: Button = root.findViewById(R.id.record_notifications_on)
    private val handler = Handler(Looper.getMainLooper())
    private val deps = (activity.application as RecordingDependencies.Provider).recordingDependencies
    private val recordings = deps.recordings
    private val announcer = RecordingAnnouncer { root.announceForAccessibility(it) }

    /** The dialog on screen (Stop's confirmation or marker note; the notification explanation: [notifications]), for tests. */
    internal var dialog: AlertDialog? = null
        private set
    private val poll = object : Runnable {
        override fun run() {
            refresh()
            handler.postDelayed(this, 500)
        }
    }

    /** Made while the activity is created, as the Activity Result API requires. Recording starts after the answer. */
    private val notifications = NotificationAsk(
        activity, R.string.record_notifications_title, R.string.record_notifications_text, R.string.record_notifications_skip,
        { deps.notificationsAnswered }, deps::setNotificationsAnswered, ::start,
    )

    init {
        stackWhenCrowded(root.findViewById(R.id.record_buttons))
        toggle.setOnClickListener { onToggle() }
        markButton.setOnClickListener { mark("") }
        markButton.setOnLongClickListener {
            askMarkerNote()
            true
        }
        root.findViewById<Button>(R.id.record_sessions).setOnClickListener {
            activity.startActivity(Intent(activity, SessionsActivity::class.java))
        }
        root.findViewById<Button>(R.id.record_open).setOnClickListener { openEnded(share = false) }
        notificationsOn.setOnClickListener { notifications.openSettings() }
        root.findViewById<Button>(R.id.record_share).setOnClickListener { openEnded(share = true) }
        // The countdown goes on through a rotation, not when the screen is left.
        activity.lifecycle.addObserver(
            LifecycleEventObserver { _, event ->
                if (event == Lifecycle.Event.ON_STOP && !activity.isChangingConfigurations) recordings.countdown.cancel()
            },
        )
        root.addOnAttachStateChangeListener(object : View.OnAttachStateChangeListener {
            override fun onViewAttachedToWindow(v: View) {
                handler.removeCallbacks(poll)
                handler.post(poll)
            }

            override fun onViewDetachedFromWindow(v: View) = handler.removeCallbacks(poll)
        })
        refresh()
    }

    private fun onToggle() {
        if (recordings.countdown.isRunning) {
            recordings.countdown.cancel()
            refresh()
        } else if (recordings.isRecording) {
            dialog = confirmStop(activity) { handler.postDelayed(::refresh, 100) }
        } else if (recordings.state.value is RecordingState.Interrupted) {
            RecordingService.continueRecording(activity)?.let { recordings.set(RecordingState.NotStarted(it)) }
            handler.postDelayed(::refresh, 100)
        } else {
            notifications.thenProceed()
        }
    }

    /** The session the last recording saved, in its detail screen; [share]: its Share started there at once. */
    private fun openEnded(share: Boolean) {
        val session = (recordings.state.value as? RecordingState.Ended)?.session ?: return
        activity.startActivity(SessionDetailActivity.intent(activity, session.name, share))
    }

    /** After the start delay, if one is set: the recording service started then (from the application, which outlives a rotation). */
    private fun start() {
        val app = activity.applicationContext
        val recordings = recordings
        recordings.countdown.start(deps.settings.value.startDelayS) {
            RecordingService.start(app)?.let { recordings.set(RecordingState.NotStarted(it)) }
        }
        // The service changes the state when it runs; show the intent at once.
        refresh()
        handler.postDelayed(::refresh, 100)
    }

    private fun notificationsAllowed(): Boolean = notifications.allowed

    /** Marks now: the time is taken at the press, the note (if any) added to it. */
    private fun mark(label: String, atNs: Long = deps.clock.elapsedRealtimeNanos()) {
        if (recordings.mark(atNs, label)) refresh()
    }

    private fun askMarkerNote() {
        val at = deps.clock.elapsedRealtimeNanos()
        val input = EditText(activity).apply {
            id = R.id.record_mark_input
            hint = activity.getString(R.string.record_mark_hint)
            inputType = InputType.TYPE_CLASS_TEXT or InputType.TYPE_TEXT_FLAG_CAP_SENTENCES
            isSingleLine = true
            filters = arrayOf(InputFilter.LengthFilter(SessionMarkers.MAX_LABEL_CHARS))
        }
        dialog = MaterialAlertDialogBuilder(activity)
            .setTitle(R.string.record_mark_title)
            .setView(input)
            .setNegativeButton(R.string.cancel, null)
            .setPositiveButton(R.string.ok) { _, _ -> mark(input.text.toString(), at) }
            .show()
    }

    private fun limitsText(l: RecordingLimits): String? {
        val d = if (l.maxDurationS > 0) DateUtils.formatElapsedTime(l.maxDurationS) else null
        val b = l.stopBatteryPercent.takeIf { it > 0 }
        return when {
            d != null && b != null -> activity.getString(R.string.record_limits_both, d, b)
            d != null -> activity.getString(R.string.record_limits, d)
            b != null -> activity.getString(R.string.record_limits_battery, b)
            else -> null
        }
    }

    fun refresh() {
        markButton.visibility = if (recordings.state.value is RecordingState.Active) View.VISIBLE else View.GONE
        val state = recordings.state.value
        after.visibility = if (state is RecordingState.Ended && state.session != null && !state.still) View.VISIBLE else View.GONE
        // The way back after "Record without": the app's notification settings.
        notificationsOn.visibility = if (notifications.declined) View.VISIBLE else View.GONE
        announcer.update(state) { RecordingAnnouncer.text(activity, it) }
        val countdown = recordings.countdown.secondsLeft.value
        if (countdown > 0) {
            toggle.text = activity.getString(R.string.record_countdown_cancel, countdown)
            toggle.contentDescription = activity.getString(R.string.record_countdown_cancel_desc)
            toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_idle))
            status.setTextIfChanged(activity.getString(R.string.record_countdown, countdown))
            return
        }
        when (val s = state) {
            is RecordingState.Preparing -> {
                toggle.setText(R.string.record_stop)
                toggle.contentDescription = activity.getString(R.string.record_stop_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_active))
                status.setTextIfChanged(s.line(activity))
            }
            is RecordingState.Active -> {
                val elapsed = s.elapsedS(deps.clock.elapsedRealtimeNanos() / 1_000_000)
                toggle.setText(R.string.record_stop)
                toggle.contentDescription = activity.getString(R.string.record_stop_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_active))
                val markers = s.markers().size
                val lines = listOfNotNull(
                    if (markers == 0) activity.getString(R.string.record_active, DateUtils.formatElapsedTime(elapsed), s.rows())
                    else activity.resources.getQuantityString(R.plurals.record_active_marked, markers, DateUtils.formatElapsedTime(elapsed), s.rows(), markers),
                    s.resumedLine(activity),
                    limitsText(s.limits),
                    if (notificationsAllowed()) null else activity.getString(R.string.record_notifications_off),
                )
                status.setTextIfChanged(lines.joinToString("\n"))
            }
            is RecordingState.Interrupted -> {
                toggle.setText(R.string.record_continue)
                toggle.contentDescription = activity.getString(R.string.record_continue_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_idle))
                status.setTextIfChanged(activity.getString(R.string.record_interrupted_bar))
            }
            else -> {
                toggle.setText(R.string.record_start)
                toggle.contentDescription = activity.getString(R.string.record_start_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_idle))
                status.setTextIfChanged(
                    when (s) {
                        is RecordingState.Ended -> RecordingService.endMessage(activity, s.result)
                        is RecordingState.NotStarted -> s.text(activity)
                        else -> activity.getString(R.string.record_idle)
                    },
                )
            }
        }
    }

    companion object {
        /** Inflates the bar into [container] of [activity]. */
        fun attach(activity: ComponentActivity, container: ViewGroup): RecordBar {
            val root = LayoutInflater.from(activity).inflate(R.layout.record_bar, container, false)
            container.addView(root)
            return RecordBar(activity, root)
        }
    }
}

/**
 * Stop, asked first (the record bar's and the banners'; the notification's Stop is the system's and
 * stops at once): "Stop recording?" with Stop and Keep recording. [stopped] runs after the Stop was sent.
 */
internal fun confirmStop(context: Context, stopped: () -> Unit = {}): AlertDialog =
    MaterialAlertDialogBuilder(context)
        .setTitle(R.string.record_stop_confirm_title)
        .setMessage(R.string.record_stop_confirm_text)
        .setNegativeButton(R.string.record_stop_confirm_keep, null)
        .setPositiveButton(R.string.record_stop) { _, _ ->
            RecordingService.stop(context)
            stopped()
        }
        .show()

/** What a starting recording is doing: repairing interrupted sessions (n of m), or preparing. The record bar and the banner show it. */
internal fun RecordingState.Preparing.line(c: Context): String = when {
    toRepair > 0 -> c.getString(R.string.record_repairing, repaired, toRepair)
    resuming -> c.getString(R.string.record_resuming)
    else -> c.getString(R.string.record_preparing)
}

/** A recording that resumed after the system killed it: what the record bar and the banner add. */
internal fun RecordingState.Active.resumedLine(c: Context): String? =
    continues?.let { c.getString(R.string.record_resumed, RecordingService.gapText(it)) }
