package dev.motionfusion.app.record

import android.Manifest
import android.content.Intent
import android.content.pm.PackageManager
import android.content.res.ColorStateList
import android.os.Build
import android.os.Handler
import android.os.Looper
import android.os.SystemClock
import android.text.format.DateUtils
import android.view.LayoutInflater
import android.view.View
import android.view.ViewGroup
import android.widget.Button
import android.widget.TextView
import androidx.activity.ComponentActivity
import androidx.activity.result.contract.ActivityResultContracts
import androidx.core.content.ContextCompat
import dev.motionfusion.app.R
import dev.motionfusion.app.sessions.SessionsActivity

/**
 * The Record/Stop button, the recording status and the way to the sessions list, inflated
 * into a host activity's container (the main screen's `record_bar`). It shows [Recordings.state]
 * (refreshed twice a second while attached to a window, for the elapsed time); the recording
 * itself lives in [RecordingService] and does not depend on this view or its activity.
 */
internal class RecordBar private constructor(private val activity: ComponentActivity, private val root: View) {
    private val toggle: Button = root.findViewById(R.id.record_toggle)
    private val status: TextView = root.findViewById(R.id.record_status)
    private val handler = Handler(Looper.getMainLooper())
    private val recordings = (activity.application as RecordingDependencies.Provider).recordingDependencies.recordings
    private val poll = object : Runnable {
        override fun run() {
            refresh()
            handler.postDelayed(this, 500)
        }
    }

    /** Registered while the activity is created, as the Activity Result API requires. */
    private val notificationPermission = activity.registerForActivityResult(ActivityResultContracts.RequestPermission()) { }

    init {
        toggle.setOnClickListener { onToggle() }
        root.findViewById<Button>(R.id.record_sessions).setOnClickListener {
            activity.startActivity(Intent(activity, SessionsActivity::class.java))
        }
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
        if (recordings.isRecording) {
            RecordingService.stop(activity)
        } else {
            requestNotificationPermission()
            RecordingService.start(activity)?.let { recordings.set(RecordingState.NotStarted(it)) }
        }
        // The service changes the state when it runs; show the intent at once.
        handler.postDelayed(::refresh, 100)
    }

    /** API 33+: ask once for the notification; recording goes on whatever the answer. */
    private fun requestNotificationPermission() {
        if (Build.VERSION.SDK_INT >= 33 &&
            ContextCompat.checkSelfPermission(activity, Manifest.permission.POST_NOTIFICATIONS) != PackageManager.PERMISSION_GRANTED
        ) {
            notificationPermission.launch(Manifest.permission.POST_NOTIFICATIONS)
        }
    }

    fun refresh() {
        when (val s = recordings.state.value) {
            is RecordingState.Preparing -> {
                toggle.setText(R.string.record_stop)
                toggle.contentDescription = activity.getString(R.string.record_stop_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_active))
                status.text = if (s.toRepair > 0) {
                    activity.getString(R.string.record_repairing, s.repaired, s.toRepair)
                } else {
                    activity.getString(R.string.record_preparing)
                }
            }
            is RecordingState.Active -> {
                val elapsed = (SystemClock.elapsedRealtime() - s.startedElapsedMs) / 1000
                toggle.setText(R.string.record_stop)
                toggle.contentDescription = activity.getString(R.string.record_stop_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_active))
                status.text = activity.getString(R.string.record_active, DateUtils.formatElapsedTime(elapsed), s.rows())
            }
            else -> {
                toggle.setText(R.string.record_start)
                toggle.contentDescription = activity.getString(R.string.record_start_desc)
                toggle.backgroundTintList = ColorStateList.valueOf(activity.getColor(R.color.record_idle))
                status.text = when (s) {
                    is RecordingState.Ended -> RecordingService.endMessage(activity, s.result)
                    is RecordingState.NotStarted -> activity.getString(R.string.record_not_started, s.reason)
                    else -> activity.getString(R.string.record_idle)
                }
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
