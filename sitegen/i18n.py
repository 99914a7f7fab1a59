"""Interface text in the two languages the course uses, chosen by ``language`` in the config."""

from __future__ import annotations

STRINGS: dict[str, dict[str, str]] = {
    "en": {
        "home": "Home", "menu": "Menu", "previous": "Previous", "next": "Next",
        "on_this_page": "On this page", "site_map": "Site Map", "search": "Search",
        "search_placeholder": "Search this site", "no_results": "No pages match",
        "results": "results", "in_this_section": "In this section", "not_found": "Page not found",
        "not_found_text": "The page you asked for is not here. Try the site map or search.",
        "breadcrumb": "Breadcrumb", "built_with": "Built with sitegen", "gallery": "Simulation gallery",
        "skip": "Skip to content", "search_needs_js": "Search needs JavaScript.",
        "duration": "Length", "parameters": "Parameters", "downloads": "Data",
        "source": "Source", "renderer": "Renderer", "trajectory": "Trajectory",
        "members": "members", "groups": "groups", "group_repo": "repo", "group_site": "site",
        "roster_json": "Download as JSON",
    },
    "zh-TW": {
        "home": "首頁", "menu": "選單", "previous": "上一頁", "next": "下一頁",
        "on_this_page": "本頁內容", "site_map": "網站地圖", "search": "搜尋",
        "search_placeholder": "搜尋本站", "no_results": "找不到符合的頁面",
        "results": "筆結果", "in_this_section": "本節頁面", "not_found": "找不到頁面",
        "not_found_text": "您要找的頁面不存在, 請改用網站地圖或搜尋.",
        "breadcrumb": "導覽路徑", "built_with": "以 sitegen 建置", "gallery": "模擬影片集",
        "skip": "跳到內容", "search_needs_js": "搜尋需要啟用 JavaScript.",
        "duration": "長度", "parameters": "參數", "downloads": "資料",
        "source": "原始碼", "renderer": "繪圖器", "trajectory": "軌跡",
        "members": "位組員", "groups": "組", "group_repo": "倉儲", "group_site": "網站",
        "roster_json": "下載 JSON",
    },
}


def strings(language: str) -> dict[str, str]:
    return STRINGS.get(language, STRINGS["en"])
