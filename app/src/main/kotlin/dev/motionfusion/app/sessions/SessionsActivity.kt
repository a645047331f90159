package dev.motionfusion.app.sessions

import dev.motionfusion.app.ui.Formats
import android.content.Context
import android.content.Intent
import android.os.Bundle
import android.text.format.DateUtils
import android.text.format.Formatter
import android.view.View
import android.view.ViewGroup
import android.widget.BaseAdapter
import android.widget.ListView
import android.widget.TextView
import androidx.appcompat.app.AppCompatActivity
import androidx.activity.viewModels
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import dev.motionfusion.app.R
import dev.motionfusion.app.ui.fitToSystemBars
import kotlinx.coroutines.launch
import java.text.DateFormat
import java.util.Date

/**
 * The recorded sessions, newest first: name, start date, duration, size, samples and each
 * stream's achieved rate, from [SessionsViewModel] (interrupted sessions are repaired before
 * listing, on the disk executor). Tap for detail.
 */
class SessionsActivity : AppCompatActivity() {
    private val adapter = Adapter()
    private val deps by lazy { (application as SessionsDependencies.Provider).sessionsDependencies }
    private val model: SessionsViewModel by viewModels { SessionsViewModel.Factory(deps) }

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_sessions)
        fitToSystemBars(findViewById(R.id.sessions_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        val list = findViewById<ListView>(R.id.sessions_list)
        list.adapter = adapter
        list.setOnItemClickListener { _, _, position, _ ->
            startActivity(Intent(this, SessionDetailActivity::class.java).putExtra(SessionDetailActivity.EXTRA_SESSION, adapter.items[position].dir.name))
        }
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) { model.state.collect { show(it) } }
        }
    }

    override fun onStart() {
        super.onStart()
        model.refresh() // a session may have been recorded, renamed or deleted meanwhile
    }

    override fun onSupportNavigateUp(): Boolean {
        finish()
        return true
    }

    /** Shows [state]: a progress text while loading, the sessions, the empty text, or why they cannot be listed. */
    internal fun show(state: SessionsUiState) {
        val items = (state as? SessionsUiState.Loaded)?.items ?: emptyList()
        adapter.items = items
        adapter.notifyDataSetChanged()
        val empty = findViewById<TextView>(R.id.sessions_empty)
        when (state) {
            SessionsUiState.Loading -> empty.setText(R.string.sessions_loading)
            is SessionsUiState.Failed -> empty.text = getString(R.string.sessions_failed, getString(state.failure.text))
            is SessionsUiState.Loaded -> empty.setText(R.string.sessions_empty)
        }
        empty.visibility = if (items.isEmpty()) View.VISIBLE else View.GONE
    }

    internal val items: List<SessionItem> get() = adapter.items

    private inner class Adapter : BaseAdapter() {
        var items: List<SessionItem> = emptyList()
        override fun getCount() = items.size
        override fun getItem(position: Int) = items[position]
        override fun getItemId(position: Int) = position.toLong()

        override fun getView(position: Int, convertView: View?, parent: ViewGroup): View {
            val v = convertView ?: layoutInflater.inflate(R.layout.session_item, parent, false)
            val item = items[position]
            v.findViewById<TextView>(R.id.session_name).text = item.dir.name
            val line1 = v.findViewById<TextView>(R.id.session_line1)
            val line2 = v.findViewById<TextView>(R.id.session_line2)
            val s = item.summary
            if (s == null) {
                line1.text = getString(R.string.session_unreadable, item.error)
                line2.text = ""
            } else {
                line1.text = describe(this@SessionsActivity, s, item.recordingNow)
                // A stream's name and rate never split over two lines (no-break spaces).
                line2.text = s.streams.filter { it.rows > 0 }.joinToString("   ") { getString(R.string.session_list_rate, shortName(this@SessionsActivity, it.name), Formats.isolated(this@SessionsActivity, "%.0f", it.rateHz)) }
            }
            line2.visibility = if (line2.text.isEmpty()) View.GONE else View.VISIBLE
            return v
        }
    }

    internal companion object {
        /** "date · duration · size", then samples, and whether recovered or recording now. */
        fun describe(activity: Context, s: SessionSummary, recordingNow: Boolean): String {
            val date = s.startWallClockMs?.let { DateFormat.getDateTimeInstance(DateFormat.MEDIUM, DateFormat.SHORT, Formats.locale(activity)).format(Date(it)) } ?: activity.getString(R.string.unknown)
            val duration = DateUtils.formatElapsedTime(s.durationNs / 1_000_000_000L)
            val size = Formatter.formatShortFileSize(activity, s.sizeBytes)
            val counts = activity.getString(R.string.session_list_counts, activity.getString(R.string.session_line1, date, duration, size), s.totalRows)
            val extra = when {
                recordingNow -> activity.getString(R.string.session_recording_now)
                s.recovered -> activity.getString(R.string.session_recovered)
                else -> null
            }.let { e ->
                val continues = s.continues ?: return@let e
                val tag = activity.getString(R.string.session_continues, continues, Formats.gap(s.gapNs))
                if (e == null) tag else activity.getString(R.string.session_list_extra, e, tag)
            }
            return if (extra == null) counts else activity.getString(R.string.session_list_extra, counts, extra)
        }

        /** Short labels for the list's rate line and the detail's plots (the session format's stream names as data, else as they are). */
        fun shortName(c: Context, stream: String): String = streamText(c, stream, short = true)

        /** A stream's name in words. */
        fun streamName(c: Context, stream: String): String = streamText(c, stream, short = false)

        private fun streamText(c: Context, stream: String, short: Boolean): String {
            val id = when (stream.lowercase()) {
                "accelerometer" -> if (short) R.string.stream_short_accelerometer else R.string.stream_accelerometer
                "accelerometer_uncalibrated" -> if (short) R.string.stream_short_accelerometer_uncalibrated else R.string.stream_accelerometer_uncalibrated
                "gyroscope" -> if (short) R.string.stream_short_gyroscope else R.string.stream_gyroscope
                "magnetometer" -> if (short) R.string.stream_short_magnetometer else R.string.stream_magnetometer
                "gyroscope_uncalibrated" -> if (short) R.string.stream_short_gyroscope_uncalibrated else R.string.stream_gyroscope_uncalibrated
                "magnetometer_uncalibrated" -> if (short) R.string.stream_short_magnetometer_uncalibrated else R.string.stream_magnetometer_uncalibrated
                "rotation_vector" -> if (short) R.string.stream_short_rotation_vector else R.string.stream_rotation_vector
                "game_rotation_vector" -> if (short) R.string.stream_short_game_rotation_vector else R.string.stream_game_rotation_vector
                else -> return stream
            }
            return c.getString(id)
        }
    }
}
