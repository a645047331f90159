package dev.motionfusion.app.stream

import android.content.ClipData
import android.content.ClipboardManager
import android.graphics.drawable.BitmapDrawable
import android.os.Build
import android.os.Bundle
import android.os.PersistableBundle
import android.text.SpannableStringBuilder
import android.text.style.ForegroundColorSpan
import android.view.View
import android.widget.EditText
import android.widget.ImageView
import android.widget.Toast
import android.widget.CompoundButton
import android.widget.TextView
import androidx.appcompat.app.AppCompatActivity
import androidx.lifecycle.Lifecycle
import androidx.lifecycle.lifecycleScope
import androidx.lifecycle.repeatOnLifecycle
import dev.motionfusion.app.R
import dev.motionfusion.app.platform.NotificationAsk
import dev.motionfusion.app.settings.SettingsRepository
import dev.motionfusion.app.ui.fitToSystemBars
import dev.motionfusion.app.ui.qrBitmap
import dev.motionfusion.stream.StreamClientInfo
import kotlinx.coroutines.launch

/**
 * The Stream screen (docs/STREAMING.md): a switch, off by default, that starts and stops the
 * [StreamController]; while on, a laptop that asks to connect (its name and address, Allow and Deny), the addresses a
 * laptop connects to (Wi-Fi and USB), the pairing
 * code, the `fusion listen` command for the first Wi-Fi address with that code (as text, as a QR code, and a button that
 * copies it: the code is on the same screen already, and a laptop that gives it is still only let in after Allow),
 * and each client with the rate it gets and what was dropped for it, a client that does not keep
 * up marked as stalled, and the optional UDP push (a `host:port` field, Push/Stop, what it sent and
 * dropped or why it did not start; the field offers the last target a push started to), and the switch "Allow remote
 * control" (off by default: a paired laptop may then start, stop and mark recordings) with the laptop in control. While the server starts
 * or stops (off the main thread) the switch waits.
 * Streaming goes on when the screen is left, under its foreground service ([StreamService]); the
 * switch here or the notification's Stop turns it off.
 */
class StreamActivity : AppCompatActivity() {
    private val controller: StreamController get() = (application as StreamDependencies.Provider).streamDependencies.streamController
    private val settings: SettingsRepository get() = (application as SettingsRepository.Provider).settingsRepository
    private lateinit var switch: CompoundButton

    /** Android 13+: the stream's notification (its Stop) explained and asked for before the first stream, as the recording's is. */
    internal val notifications = NotificationAsk(
        this, R.string.stream_notifications_title, R.string.stream_notifications_text, R.string.stream_notifications_skip,
        { settings.notificationsAnswered }, { settings.markNotificationsAnswered() }, { controller.start() },
    )

    override fun onCreate(savedInstanceState: Bundle?) {
        super.onCreate(savedInstanceState)
        setContentView(R.layout.activity_stream)
        fitToSystemBars(findViewById(R.id.stream_root))
        setSupportActionBar(findViewById(R.id.toolbar))
        supportActionBar?.setDisplayHomeAsUpEnabled(true)
        switch = findViewById(R.id.stream_switch)
        show(controller.state.value)
        switch.setOnCheckedChangeListener { _, on ->
            if (switch.tag !== SHOWING) if (on) notifications.thenProceed() else controller.stop()
        }
        val remote = findViewById<CompoundButton>(R.id.stream_remote_switch)
        remote.isChecked = controller.remoteControlAllowed
        remote.setOnCheckedChangeListener { _, on -> controller.allowRemoteControl(on) }
        val target = findViewById<EditText>(R.id.stream_udp_target)
        findViewById<View>(R.id.stream_copy).setOnClickListener { copyCommand() }
        findViewById<View>(R.id.stream_udp_button).setOnClickListener {
            val udp = (controller.state.value as? StreamState.On)?.udp
            if (udp is UdpView.Pushing || udp is UdpView.Starting) controller.stopUdp() else controller.pushUdp(target.text.toString())
        }
        lifecycleScope.launch {
            // The last target, once the store has been read, unless something was typed meanwhile.
            settings.awaitLoaded()
            if (target.text.isEmpty()) target.setText(settings.udpTarget)
        }
        lifecycleScope.launch {
            repeatOnLifecycle(Lifecycle.State.STARTED) { controller.state.collect { show(it) } }
        }
    }

    override fun onSupportNavigateUp(): Boolean {
        finish()
        return true
    }

    private fun show(state: StreamState) {
        val on = state as? StreamState.On
        val checked = on != null || state == StreamState.Starting
        if (switch.isChecked != checked) {
            // Shown without starting or stopping: the state already says it.
            switch.tag = SHOWING
            switch.isChecked = checked
            switch.tag = null
        }
        // Starting or stopping: the switch waits for the server.
        switch.isEnabled = state != StreamState.Starting && state != StreamState.Stopping
        findViewById<TextView>(R.id.stream_message).let {
            val message = when (state) {
                is StreamState.Failed -> getString(R.string.stream_failed, getString(state.text))
                StreamState.Starting -> getString(R.string.stream_starting)
                StreamState.Stopping -> getString(R.string.stream_stopping)
                else -> null
            }
            it.text = message ?: ""
            it.visibility = if (message != null) View.VISIBLE else View.GONE
            it.setTextAppearance(if (state is StreamState.Failed) R.style.Warning else R.style.Note)
        }
        findViewById<TextView>(R.id.stream_controlled_by).let {
            val by = on?.controlledBy
            it.text = by?.let { b -> getString(R.string.stream_controlled_by, b) } ?: ""
            it.visibility = if (by != null) View.VISIBLE else View.GONE
        }
        findViewById<View>(R.id.stream_note).visibility = if (on == null) View.VISIBLE else View.GONE
        findViewById<View>(R.id.stream_details).visibility = if (on == null) View.GONE else View.VISIBLE
        if (on == null) return
        showRequest(on.clients.filter { it.awaitingConfirmation })
        findViewById<TextView>(R.id.stream_code).text = on.code
        findViewById<TextView>(R.id.stream_addresses).text =
            if (on.addresses.isEmpty()) getString(R.string.stream_no_address)
            else on.addresses.joinToString("\n") { getString(R.string.stream_address, it, on.port.toString()) }
        // The port as typed on a laptop: ASCII digits whatever the language (an Arabic phone formats %d in its own digits).
        findViewById<TextView>(R.id.stream_usb).text = getString(R.string.stream_usb, on.port.toString())
        showCommand(on)
        showUdp(on.udp)
        val locale = resources.configuration.locales[0]
        val warning = getColor(R.color.warning)
        findViewById<TextView>(R.id.stream_clients).text =
            if (on.clients.isEmpty()) getString(R.string.stream_waiting)
            else SpannableStringBuilder().apply {
                for ((i, c) in on.clients.withIndex()) {
                    if (i > 0) append('\n')
                    when {
                        c.awaitingConfirmation -> append(getString(R.string.stream_client_asking, c.address))
                        !c.paired -> append(getString(R.string.stream_client_unpaired, c.address))
                        // A client whose messages are being dropped: its own text, in the warning colour.
                        c.stalled -> append(getString(R.string.stream_client_stalled, c.address, c.sent, c.dropped), ForegroundColorSpan(warning), 0)
                        else -> append(getString(R.string.stream_client, c.address, String.format(locale, "%.0f", c.achievedRateHz), c.sent, c.dropped))
                    }
                }
            }
    }

    /** The command shown; null without a network address (USB needs `adb forward` first: its line says so). */
    private var command: String? = null

    /** The `fusion listen` command for the first address, as text and QR code; redrawn only when it changes (a new code). */
    private fun showCommand(on: StreamState.On) {
        val address = on.addresses.firstOrNull()
        val text = address?.let { getString(R.string.stream_command, it, on.port.toString(), on.code) }
        findViewById<View>(R.id.stream_laptop).visibility = if (text == null) View.GONE else View.VISIBLE
        if (text == command) return
        command = text
        findViewById<TextView>(R.id.stream_command).text = text ?: ""
        findViewById<ImageView>(R.id.stream_qr).setImageDrawable(
            text?.let { t -> BitmapDrawable(resources, qrBitmap(t)).apply { isFilterBitmap = false } },
        )
    }

    /**
     * The command to the clipboard, marked sensitive (it holds the code: Android 13+ then hides it in the clipboard's
     * preview); Android 13+ confirms a copy itself, earlier versions get a toast.
     */
    private fun copyCommand() {
        val text = command ?: return
        val clip = ClipData.newPlainText(getString(R.string.stream_laptop_title), text)
        clip.description.extras = PersistableBundle().apply { putBoolean(EXTRA_IS_SENSITIVE, true) }
        getSystemService(ClipboardManager::class.java).setPrimaryClip(clip)
        if (Build.VERSION.SDK_INT < 33) Toast.makeText(this, R.string.stream_copied, Toast.LENGTH_SHORT).show()
    }

    /** The first laptop that asks to connect, with Allow and Deny; how many more ask after it. */
    private fun showRequest(asking: List<StreamClientInfo>) {
        findViewById<View>(R.id.stream_request).visibility = if (asking.isEmpty()) View.GONE else View.VISIBLE
        val first = asking.firstOrNull() ?: return
        findViewById<TextView>(R.id.stream_request_text).text =
            first.name?.let { getString(R.string.stream_request_named, it, first.address) } ?: getString(R.string.stream_request_unnamed, first.address)
        findViewById<TextView>(R.id.stream_request_more).let {
            val more = asking.size - 1
            it.text = if (more > 0) resources.getQuantityString(R.plurals.stream_request_more, more, more) else ""
            it.visibility = if (more > 0) View.VISIBLE else View.GONE
        }
        findViewById<View>(R.id.stream_request_allow).setOnClickListener { controller.allow(first.id) }
        findViewById<View>(R.id.stream_request_deny).setOnClickListener { controller.deny(first.id) }
    }

    private fun showUdp(udp: UdpView?) {
        if (udp is UdpView.Pushing) settings.rememberUdpTarget(udp.target)
        val active = udp is UdpView.Pushing || udp is UdpView.Starting
        findViewById<TextView>(R.id.stream_udp_button).setText(if (active) R.string.stream_udp_stop else R.string.stream_udp_start)
        findViewById<EditText>(R.id.stream_udp_target).isEnabled = !active
        findViewById<TextView>(R.id.stream_udp_status).let {
            it.text = when (udp) {
                null -> ""
                is UdpView.Starting -> getString(R.string.stream_udp_starting, udp.target)
                is UdpView.Pushing -> getString(R.string.stream_udp_pushing, udp.target, udp.sent, udp.dropped)
                is UdpView.Failed -> udp.text?.let { r -> getString(R.string.stream_udp_failed, getString(r)) } ?: getString(R.string.stream_udp_invalid)
            }
            it.visibility = if (udp == null) View.GONE else View.VISIBLE
            it.setTextAppearance(if (udp is UdpView.Failed) R.style.Warning else R.style.Body)
        }
    }

    private companion object {
        val SHOWING = Any()
        /** `ClipDescription.EXTRA_IS_SENSITIVE` (API 33), by value: read from API 33 on, ignored before. */
        const val EXTRA_IS_SENSITIVE = "android.content.extra.IS_SENSITIVE"
    }
}
